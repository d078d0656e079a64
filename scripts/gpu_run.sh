#!/bin/sh
# masq's GPU check, run from the GPU bundle (scripts/gpu_bundle.sh copies this file into
# it as run.sh): run.sh [--quick] OUTDIR
#
# Needs nothing from the machine but glibc, a POSIX shell with coreutils, and the GPU
# driver. Finds NVIDIA's ICDs where GPU containers put them (/usr/local/nvidia), prints
# `masq info`, then runs each step under its own timeout (the timeouts sum to 6 minutes;
# --quick: the sealed test's small run), smallest first, checking before each step that
# no kernel of the last one still holds the GPU:
#   1. the hang diagnosis: the default scene's camera rays against the oracle on the
#      vulkan backend in every form of the suspects' switches (stack form, array access,
#      float controls), each fault reported with its rays' state (MASQ_DIAGNOSE);
#   2. the cross-backend tests against the long-double oracle on every GPU backend;
#   3. the speed table: the default scene, the bear fur as capsules and as curves, the
#      paper's fig3 grid, on vulkan, opencl, rtpipeline and the cpu backend (every core);
#   4. last, the traversal without its step budget (MASQ_STEP_CHECK=off), as the first
#      H200 run traced it, to tell whether the kernels' fixes or the budget ended the hang.
# Writes as it goes into OUTDIR six files at most (what a GPU lease brings back): log.txt
# (every command's output), RESULTS.md (each step's verdict and tables), speed.json (the
# bench runs' raw figures), fig3.json and fig3.md (the suite) and report.md (fig3 beside
# the repository's quick run); scratch goes to a folder of its own under $TMPDIR.
# Exit status: 0 when every step passed.
set -u

usage() { sed -n '2,21p' "$0" | sed 's/^# \{0,1\}//'; }

quick=0 out=""
for a in "$@"; do
  case "$a" in
    --quick) quick=1 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "run.sh: unknown option '$a'" >&2; usage >&2; exit 2 ;;
    *) [ -z "$out" ] || { echo "run.sh: one OUTDIR only" >&2; exit 2; }; out=$a ;;
  esac
done
[ -n "$out" ] || { usage >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out" || exit 1
out=$(cd "$out" && pwd)
log="$out/log.txt"
md="$out/RESULTS.md"
: >"$log"
scratch="${TMPDIR:-/tmp}/masq-gpu-run.$$"
mkdir -p "$scratch" || exit 1
bin="$here/bin"
failed=0

say() { echo "$*" | tee -a "$log"; }
note() { echo "$*" >>"$md"; }

# ---------------------------------------------------------------- drivers and runtime
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ] && [ -e "$nvidia_icd" ]; then
  export VK_ADD_DRIVER_FILES="$nvidia_icd"
fi
nvidia_egl=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
if [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ] && [ -e "$nvidia_egl" ]; then
  export __EGL_VENDOR_LIBRARY_FILENAMES="$nvidia_egl"
fi
# That ICD names its library without a path, in a folder outside the loader's search.
if [ -d /usr/local/nvidia/lib64 ]; then
  export LD_LIBRARY_PATH="${LD_LIBRARY_PATH:+$LD_LIBRARY_PATH:}/usr/local/nvidia/lib64"
fi
# NVIDIA's OpenCL library comes without an ICD file there: list it for the ICD loader.
nvidia_ocl=/usr/local/nvidia/lib64/libnvidia-opencl.so.1
if [ -z "${OCL_ICD_VENDORS:-}" ] && [ -e "$nvidia_ocl" ]; then
  export OCL_ICD_VENDORS="$scratch/icd"
  mkdir -p "$OCL_ICD_VENDORS"
  for f in /etc/OpenCL/vendors/*.icd; do [ -e "$f" ] && cp "$f" "$OCL_ICD_VENDORS/"; done
  echo "$nvidia_ocl" >"$OCL_ICD_VENDORS/nvidia.icd"
fi
# What NVIDIA's Vulkan ICD loads (GLVND, X11 client libraries), from the bundle where
# the machine lacks it: each missing one linked into a folder on the library path.
mkdir -p "$scratch/driver"
driver_from_bundle=""
for f in "$here"/lib/driver/*; do
  [ -e "$f" ] || continue
  n=${f##*/}
  found=0
  for d in /lib/x86_64-linux-gnu /usr/lib/x86_64-linux-gnu /lib64 /usr/lib64 /usr/local/nvidia/lib64; do
    if [ -e "$d/$n" ]; then found=1; break; fi
  done
  if [ $found -eq 0 ]; then
    ln -s "$f" "$scratch/driver/$n"
    driver_from_bundle="$driver_from_bundle $n"
  fi
done
[ -n "$driver_from_bundle" ] && export LD_LIBRARY_PATH="${LD_LIBRARY_PATH:+$LD_LIBRARY_PATH:}$scratch/driver"
# The C++ runtime: the system's where it has every symbol version the bundle needs (a
# driver's libraries may need a newer one than the bundle's), else the bundle's.
cxx_ok=1
for lib in libstdc++.so.6 libgcc_s.so.1; do
  sys=""
  for d in /lib/x86_64-linux-gnu /usr/lib/x86_64-linux-gnu /lib64 /usr/lib64 /lib /usr/lib; do
    if [ -e "$d/$lib" ]; then sys="$d/$lib"; break; fi
  done
  if [ -z "$sys" ]; then cxx_ok=0; continue; fi
  while read -r v; do
    case "$v" in GLIBCXX_*|CXXABI_*) [ "$lib" = libstdc++.so.6 ] || continue ;; GCC_*) [ "$lib" = libgcc_s.so.1 ] || continue ;; esac
    grep -q "$v" "$sys" || cxx_ok=0
  done <"$here/lib/fallback/NEEDS"
done
if [ $cxx_ok -eq 1 ]; then
  cxx="the system's (it has every version in lib/fallback/NEEDS)"
else
  export LD_LIBRARY_PATH="$here/lib/fallback${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  cxx="the bundle's (lib/fallback: the system's is missing or older)"
fi
# No validation layer in the bundle; a hung kernel is an error after this long.
export MASQ_VK_VALIDATION=0 MASQ_VK_WAIT_SECONDS=${MASQ_VK_WAIT_SECONDS:-10}
export MASQ_DIAGNOSE=${MASQ_DIAGNOSE:-8}
export MASQ_DATA="$here/data"

{
  echo "# masq GPU run"
  echo
  echo "Bundle: $(sed -n 2p "$here/BUILD_INFO"), $(sed -n 3p "$here/BUILD_INFO")"
  echo "Machine: $(uname -srm), $(nproc 2>/dev/null || echo "?") cores; run $(date -u +%Y-%m-%dT%H:%MZ)"
  echo "C++ runtime: $cxx; Vulkan ICDs: ${VK_DRIVER_FILES:-${VK_ICD_FILENAMES:-the loader's search path}}${VK_ADD_DRIVER_FILES:+ + $VK_ADD_DRIVER_FILES}"
  echo "Driver support libraries from the bundle:${driver_from_bundle:- none (the machine has them)}"
  [ $quick -eq 1 ] && echo "Mode: --quick (the sealed test's small run)"
  echo
} >"$md"
say "run.sh: output in $out (log.txt has every command's output)"

if command -v nvidia-smi >/dev/null 2>&1; then
  note '```'
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,utilization.gpu --format=csv 2>&1 | tee -a "$log" >>"$md"
  note '```'
fi

# ---------------------------------------------------------------- steps
# Before a step: the GPU idle (utilisation under 10% within 20 s), where nvidia-smi can
# tell; a step that left a kernel running would make every later figure meaningless.
gpu_idle() {
  command -v nvidia-smi >/dev/null 2>&1 || return 0
  i=0
  while [ $i -lt 20 ]; do
    u=$(nvidia-smi --query-gpu=utilization.gpu --format=csv,noheader,nounits 2>/dev/null | head -n1 | tr -dc '0-9')
    [ -z "$u" ] && return 0
    [ "$u" -lt 10 ] && return 0
    sleep 1
    i=$((i + 1))
  done
  return 1
}

gpu_busy=0
# step NAME SECONDS COMMAND...: runs COMMAND under its timeout, output to the log, one
# verdict line to RESULTS.md. Returns the command's status (124/137: timed out).
step() {
  name=$1 limit=$2
  shift 2
  if [ $gpu_busy -eq 1 ] || ! gpu_idle; then
    gpu_busy=1
    say "== $name: not run: the GPU is still busy after the last step"
    note "- **$name**: not run (a kernel of an earlier step still held the GPU)"
    failed=1
    return 125
  fi
  say "== $name (at most ${limit} s): $*"
  t0=$(date +%s)
  timeout -k 5 "$limit" "$@" >>"$log" 2>&1
  rc=$?
  t1=$(date +%s)
  case $rc in
    0) verdict="passed" ;;
    124|137) verdict="**timed out** after ${limit} s" ;;
    *) verdict="**failed** (exit $rc)" ;;
  esac
  say "== $name: $verdict in $((t1 - t0)) s"
  note "- **$name**: $verdict in $((t1 - t0)) s"
  [ $rc -eq 0 ] || failed=1
  return $rc
}

# The last error lines of the log (a failed step's diagnosis) into RESULTS.md.
quote_errors() {
  grep -E "stopped|Failure|FAILED|error|did not finish|hit/miss|ray [0-9]+:" "$log" | tail -n "$1" |
    sed 's/^/    /' >>"$md"
}

note
note "## masq info"
note '```'
timeout 60 "$bin/masq" info 2>&1 | tee -a "$log" >>"$md"
note '```'
# A Vulkan driver that did not load: the loader's own account of why.
if "$bin/masq" info 2>/dev/null | grep -q '^vulkan *unavailable'; then
  note "The Vulkan loader on that (VK_LOADER_DEBUG=error,warn,driver):"
  note '```'
  VK_LOADER_DEBUG=error,warn,driver timeout 30 "$bin/masq" info 2>&1 >/dev/null | tee -a "$log" |
    grep -iE 'error|warn|fail|cannot|not found|dlopen|libGL|icd' | head -n 25 >>"$md"
  note '```'
fi

# 1. The hang diagnosis: every form of the suspects' switches (docs/kernels.md, "Stack
# forms"; MASQ_VK_ADDRESSING; MASQ_VK_FLOAT_CONTROLS), the default scene's camera rays
# against the oracle on vulkan. A form that faults names its rays' state in the log.
note
note "## 1. Hang diagnosis: vulkan, default scene camera rays against the oracle"
if [ $quick -eq 1 ]; then
  forms="fixed,addressed,on"
  limit=120
else
  forms="fixed,addressed,on sized,addressed,on fixed,bound,on sized,bound,on fixed,addressed,off"
  limit=9 # 2-4 s each on the H200
fi
for form in $forms; do
  stack=${form%%,*} rest=${form#*,}
  access=${rest%%,*} fc=${rest#*,}
  if ! step "stack $stack, arrays $access, float controls $fc" $limit \
      env MASQ_STACK_FORM="$stack" MASQ_VK_ADDRESSING="$access" MASQ_VK_FLOAT_CONTROLS="$fc" MASQ_TEST_BACKENDS=vulkan \
      "$bin/test_cross_backend" --gtest_brief=1 --gtest_filter=CrossBackend.DefaultSceneCamera; then
    quote_errors 6
  fi
done

# 2. Every GPU backend against the oracle (rayquery where the device has it).
note
note "## 2. Cross-backend tests against the oracle"
backends=$("$bin/masq" info 2>/dev/null | awk '$2 == "available" && $1 != "cpu" { printf "%s%s", sep, $1; sep = "," }')
note "GPU backends available: ${backends:-none}"
# A gtest filter of the cases named after those backends (EveryBackend/Occlusion.X/vulkan_ref...).
by_backend=$(echo "$backends" | tr ',' '\n' | sed 's/.*/*&*/' | tr '\n' ':' | sed 's/:$//')
if [ -z "$backends" ]; then
  note "- not run: no GPU backend opened (masq info above says why)"
  failed=1
elif [ $quick -eq 1 ]; then
  step "traversal faults (corrupt structure, full stack)" 180 \
    "$bin/test_traversal_faults" --gtest_brief=1 --gtest_filter="*vulkan*:TraceFaults.*" || quote_errors 6
else
  # The cases that fit the step (the whole binary needs several minutes there: each
  # variant is a driver compile of 0.3-2 s on NVIDIA's OpenCL, first H200 bundle run).
  step "cross_backend: every method, instanced scenes, every primitive, invalid rays, counters" 85 \
    env MASQ_TEST_BACKENDS="cpu,$backends" "$bin/test_cross_backend" --gtest_brief=1 \
    --gtest_filter="CrossBackend.DefaultSceneCamera:CrossBackend.RandomInstancedScenes:CrossBackend.InvalidRays*:CrossBackend.ComputeBackendsVisitWhatTheCpuVisits:CrossBackend.SingleIdentityInstance*:Types/EveryPrimitive.BundleCamera/*" ||
    quote_errors 10
  step "occlusion (shadow rays, early exit)" 15 \
    "$bin/test_occlusion" --gtest_brief=1 --gtest_filter="$by_backend" || quote_errors 6
  step "node formats w4, w8, q8, o4 agree" 35 \
    "$bin/test_node_formats_cross" --gtest_brief=1 --gtest_filter="$by_backend" || quote_errors 6
  step "traversal faults (corrupt structure, full stack)" 15 \
    "$bin/test_traversal_faults" --gtest_brief=1 --gtest_filter="$by_backend:TraceFaults.*" || quote_errors 6
fi

# 3. Speed: device time and wall time per backend x method (masq bench prints both);
# 2048 x 2048 camera rays fill a GPU many times over; the cpu backend (every core) gets
# 1024 x 1024 in its own rows, where 4M rays would take most of the step.
note
note "## 3. Speed"
# (sh has no locals: the b_ names keep clear of step's.)
bench() { # NAME SECONDS SIZE REPS BACKENDS ARGS...
  b_name=$1 b_limit=$2 b_size=$3 b_reps=$4 b_backends=$5
  shift 5
  # shellcheck disable=SC2086 # the backends are separate arguments
  if step "bench $b_name" "$b_limit" "$bin/masq" bench -q --wide --backend $b_backends --rays primary --width "$b_size" \
      --height "$b_size" --warmup 1 --reps "$b_reps" --json "$scratch/speed_$b_name.json" "$@"; then
    note '```'
    # The tables bench printed: the log's lines between this step's header and its verdict.
    awk -v n="== bench $b_name (" 'index($0, n) == 1 { on = 1; next } on && /^== / { on = 0 } on' "$log" |
      grep -E '^(scene|backend|cpu|vulkan|opencl|rtpipeline|rayquery) ' >>"$md"
    note '```'
  else
    quote_errors 4
  fi
}
bear="$here/data/hair/tressfx3_bear.tfx"
if [ $quick -eq 1 ]; then
  bench default 120 128 1 "cpu vulkan" --method ref masq cluster
else
  gpus=$(echo "$backends" | tr ',' ' ')
  bench default 20 2048 3 "$gpus" --method ref masq cluster
  bench bear_capsules 25 2048 3 "$gpus" --file "$bear" --prim capsule --method ref masq
  bench bear_curves 45 2048 2 "$gpus" --file "$bear" --prim curve --method ref masq
  bench cpu_bear_capsules 10 1024 2 cpu --file "$bear" --prim capsule --method ref masq
  # shellcheck disable=SC2086
  if step "fig3 grid (the paper's Fig. 3, quick)" 45 "$bin/masq" bench -q --suite fig3 --quick --backend $gpus cpu \
      --auto-by model --out "$scratch/fig3" --data "$here/data"; then
    cp "$scratch/fig3/results.json" "$out/fig3.json"
    cp "$scratch/fig3/RESULTS.md" "$out/fig3.md" && note "The suite's own tables: fig3.md (raw: fig3.json)"
    if "$bin/masq" report "$here/baseline/results.json" "$scratch/fig3/results.json" \
        --label "$here/baseline/results.json=repository" --label "$scratch/fig3/results.json=gpu" \
        --out "$scratch/report" >>"$log" 2>&1; then
      cp "$scratch/report/RESULTS.md" "$out/report.md" && note "fig3 beside the repository's quick run: report.md"
    fi
  fi
  # What each kernel variant costs a GPU thread, as the driver compiled it (registers,
  # local memory), in both stack forms: VK_KHR_pipeline_executable_properties.
  if step "pipeline statistics (fixed and sized stacks)" 10 sh -c "for f in fixed sized; do \
      MASQ_STACK_FORM=\$f MASQ_VK_PIPELINE_STATS=1 '$bin/masq' bench -q --backend vulkan --method ref masq \
        --rays primary --width 64 --height 64 --warmup 0 --reps 1 >/dev/null || exit 1; done"; then
    note '```'
    grep "pipeline statistics" "$log" | sed 's/^masq: vulkan pipeline statistics: //' >>"$md"
    note '```'
  fi
fi

# 4. The traversal without its step budget, last (it may hang as the first run did).
if [ $quick -eq 0 ]; then
  note
  note "## 4. Without the step budget (MASQ_STEP_CHECK=off), as the first H200 run traced"
  step "vulkan, every method, no step budget" 10 env MASQ_STEP_CHECK=off MASQ_TEST_BACKENDS=vulkan \
    "$bin/test_cross_backend" --gtest_brief=1 --gtest_filter=CrossBackend.DefaultSceneCamera || quote_errors 4
fi

# The bench runs' raw figures in one file: {"name": <its --json>, ...}.
first=1
{
  echo "{"
  for f in "$scratch"/speed_*.json; do
    [ -e "$f" ] || continue
    n=${f##*/speed_}
    [ $first -eq 1 ] || echo ","
    first=0
    printf '"%s": ' "${n%.json}"
    cat "$f"
  done
  echo "}"
} >"$out/speed.json"
rm -rf "$scratch"

note
if [ $failed -eq 0 ]; then note "Every step passed."; else note "Some steps did not pass: log.txt has their output."; fi
say "run.sh: done ($([ $failed -eq 0 ] && echo 'every step passed' || echo 'some steps failed')); $md"
exit $failed
