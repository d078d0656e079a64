#!/usr/bin/env bash
# One command for a GPU user: set up (scripts/setup.sh skips what is installed), build,
# list every device (masq info), run the cross-backend tests on the chosen device, run the
# quick bench suites there and write bench/results-<device>/RESULTS.md.
#
#   bash scripts/gpu_check.sh                      the best-ranked devices (discrete GPU first)
#   bash scripts/gpu_check.sh --device nvidia      SEL: an index of masq info's list or a name
#                                                  substring, for Vulkan and OpenCL
#   bash scripts/gpu_check.sh --device vulkan=1,opencl=0   each API its own (rayquery=, rtpipeline= too)
#   bash scripts/gpu_check.sh --no-setup           skip scripts/setup.sh (no package manager)
#   bash scripts/gpu_check.sh --smoke --build-dir DIR --out DIR
#                                                  the test suite's run: no setup, no build, two
#                                                  test cases, quick fig3 on vulkan alone
#
# Drivers: the Vulkan loader honours VK_DRIVER_FILES / VK_ICD_FILENAMES (only those ICDs)
# and VK_ADD_DRIVER_FILES (more ICDs); the OpenCL ICD loader honours OCL_ICD_VENDORS.
# Where none is set and an NVIDIA ICD lies outside the loader's search path
# (/usr/local/nvidia/share/vulkan/icd.d, as some GPU containers provide it), it is added
# with VK_ADD_DRIVER_FILES. The ICDs in use are printed first.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; }

device="" setup=1 build=1 smoke=0 build_dir=build out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --device) [ $# -ge 2 ] || { echo "gpu_check: --device needs a value" >&2; exit 2; }; device=$2; shift 2 ;;
    --device=*) device=${1#--device=}; shift ;;
    --no-setup) setup=0; shift ;;
    --smoke) smoke=1; setup=0; build=0; shift ;;
    --build-dir) [ $# -ge 2 ] || { echo "gpu_check: --build-dir needs a value" >&2; exit 2; }; build_dir=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || { echo "gpu_check: --out needs a value" >&2; exit 2; }; out=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "gpu_check: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done

# --device -> the selectors' environment variables, which masq and the tests read
# (host/device_choice.h; the same syntax as masq's --device: a comma not followed by
# api= belongs to the device name).
if [ -n "$device" ]; then
  case "$device" in
    vulkan=*|rayquery=*|rtpipeline=*|opencl=*)
      api="" value=""
      set_selector() {
        case "$1" in
          vulkan) export MASQ_VK_DEVICE="$2" ;;
          rayquery) export MASQ_RQ_DEVICE="$2" ;;
          rtpipeline) export MASQ_RT_DEVICE="$2" ;;
          opencl) export MASQ_CL_DEVICE="$2" ;;
        esac
      }
      IFS=',' read -r -a parts <<<"$device"
      for part in "${parts[@]}"; do
        case "$part" in
          vulkan=*|rayquery=*|rtpipeline=*|opencl=*)
            [ -n "$api" ] && set_selector "$api" "$value"
            api=${part%%=*} value=${part#*=} ;;
          *) value="$value,$part" ;;
        esac
      done
      set_selector "$api" "$value" ;;
    *=*) echo "gpu_check: --device '$device': expected SEL or api=SEL[,api=SEL] with api vulkan, rayquery, rtpipeline or opencl" >&2
         exit 2 ;;
    *) export MASQ_VK_DEVICE="$device" MASQ_CL_DEVICE="$device" ;;
  esac
fi

# The ICDs.
nvidia_icds=(/usr/local/nvidia/share/vulkan/icd.d/*.json)
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ] && [ -e "${nvidia_icds[0]}" ] && [ -z "${VK_ADD_DRIVER_FILES:-}" ]; then
  VK_ADD_DRIVER_FILES=$(IFS=:; echo "${nvidia_icds[*]}")
  export VK_ADD_DRIVER_FILES
fi
# That ICD names its library (libGLX_nvidia.so.0) without a path, in a folder outside
# the dynamic loader's (seen on an H200 container: without it, VK_ERROR_INCOMPATIBLE_DRIVER).
if [ -e "${nvidia_icds[0]}" ] && [ -d /usr/local/nvidia/lib64 ]; then
  export LD_LIBRARY_PATH="${LD_LIBRARY_PATH:+$LD_LIBRARY_PATH:}/usr/local/nvidia/lib64"
fi
# Such containers also ship NVIDIA's OpenCL library without an ICD file: list it, with
# the registered ones, in a folder of our own for the OpenCL ICD loader.
nvidia_ocl=/usr/local/nvidia/lib64/libnvidia-opencl.so.1
if [ -z "${OCL_ICD_VENDORS:-}" ] && [ -e "$nvidia_ocl" ] && ! grep -qs nvidia /etc/OpenCL/vendors/*.icd; then
  OCL_ICD_VENDORS=$(mktemp -d)
  cp /etc/OpenCL/vendors/*.icd "$OCL_ICD_VENDORS"/ 2>/dev/null || true
  echo "$nvidia_ocl" >"$OCL_ICD_VENDORS/nvidia.icd"
  export OCL_ICD_VENDORS
fi
if [ -n "${VK_DRIVER_FILES:-}" ]; then
  echo "Vulkan ICDs: VK_DRIVER_FILES=$VK_DRIVER_FILES (only these)"
elif [ -n "${VK_ICD_FILENAMES:-}" ]; then
  echo "Vulkan ICDs: VK_ICD_FILENAMES=$VK_ICD_FILENAMES (only these)"
else
  found=$(ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json /usr/local/share/vulkan/icd.d/*.json 2>/dev/null | tr '\n' ' ' || true)
  echo "Vulkan ICDs: the loader's search path: ${found:-none}${VK_ADD_DRIVER_FILES:+ + VK_ADD_DRIVER_FILES=$VK_ADD_DRIVER_FILES}"
fi
if [ -n "${OCL_ICD_VENDORS:-}" ]; then
  echo "OpenCL ICDs: OCL_ICD_VENDORS=$OCL_ICD_VENDORS"
else
  found=$(ls /etc/OpenCL/vendors/*.icd 2>/dev/null | tr '\n' ' ' || true)
  echo "OpenCL ICDs: ${found:-none}"
fi
for v in MASQ_VK_DEVICE MASQ_RQ_DEVICE MASQ_CL_DEVICE; do
  [ -n "${!v:-}" ] && echo "selector: $v=${!v}"
done

if [ $setup -eq 1 ]; then bash scripts/setup.sh; fi
if [ $build -eq 1 ]; then bash scripts/build.sh; fi
masq="$build_dir/masq"
[ -x "$masq" ] || { echo "gpu_check: $masq not built (run without --smoke, or pass --build-dir)" >&2; exit 1; }

echo "== devices"
# info exits 1 only when no backend runs at all; a selector naming nothing shows in its
# list, and is an error below.
info=$("$masq" info) || { echo "$info"; echo "gpu_check: no backend runs here" >&2; exit 1; }
echo "$info"

# The results folder is named after the device the vulkan backend runs on (else opencl's,
# else the host's): lower case, runs of other characters as one '-'.
device_name=$(awk '$1 == "vulkan" && $2 == "available" { $1 = $2 = ""; print; exit }' <<<"$info")
[ -n "$device_name" ] || device_name=$(awk '$1 == "opencl" && $2 == "available" { $1 = $2 = ""; print; exit }' <<<"$info")
[ -n "$device_name" ] || device_name=cpu
device_name=${device_name%% \[*} # without the driver
device_name=$(sed 's/^ *//; s/ *$//' <<<"$device_name")
slug=$(tr 'A-Z' 'a-z' <<<"$device_name" | sed 's/[^a-z0-9]\{1,\}/-/g; s/^-//; s/-$//' | cut -c1-48 | sed 's/-$//')
[ -n "$out" ] || out="bench/results-$slug"

# A selector that names no device is an error before anything runs (masq names it and the
# devices there are in its listing).
if grep -q 'matches no' <<<"$info"; then
  echo "gpu_check: $(grep -m1 -o "[A-Z_-]*DEVICE='.*" <<<"$info")" >&2
  exit 1
fi

# A backend this machine lacks (rayquery on a GPU without VK_KHR_ray_query, such as an
# H100 or H200, where rtpipeline is the driver-traversal check) is skipped by the tests,
# with its reason above, instead of failing them.
if grep -q '^[a-z]* *unavailable' <<<"$info"; then
  export MASQ_ALLOW_MISSING_BACKENDS=1
  grep '^[a-z]* *unavailable' <<<"$info" | sed 's/^/gpu_check: skipped by the tests: /'
fi
# A kernel that never finishes (a compute GPU has no watchdog) is an error after this
# long, naming the device, instead of a hang (host/vulkan/vk_context.h).
export MASQ_VK_WAIT_SECONDS=${MASQ_VK_WAIT_SECONDS:-120}

echo "== cross-backend tests on the chosen devices"
if [ $smoke -eq 1 ]; then
  # Two cases straight from the test binaries (this runs inside ctest itself).
  "$build_dir/tests/test_cross_backend" --gtest_brief=1 --gtest_filter='CrossBackend.DefaultSceneCamera'
  "$build_dir/tests/test_device_choice" --gtest_brief=1 --gtest_filter='RealDevices.*'
else
  # Every backend against the oracle and each other, and the device choice itself.
  ctest --test-dir "$build_dir" \
    -R '^(CrossBackend|Types/EveryPrimitive|Backends/NodeFormatsAgree|EveryBackend/Occlusion|Backends/(Bv)?TraversalFaults|TraceFaults|DeviceChoice|RealDevices)\.|^python_pytest$' \
    --output-on-failure --timeout 600 -j"$(nproc)"
fi

echo "== quick suites -> $out"
if [ $smoke -eq 1 ]; then
  # The smallest run of a suite: quick fig3 on the vulkan backend, auto kept by the cost
  # model (no pilot traces). It proves the path (devices, tables, RESULTS.md), not numbers.
  "$masq" bench --suite fig3 --quick --quiet --auto-by model --backend vulkan --out "$out"
else
  "$masq" bench --suite all --quick --quiet --out "$out"
  /usr/bin/python3 scripts/plot_results.py "$out" || echo "gpu_check: plots skipped (matplotlib missing?)"
fi
[ -s "$out/RESULTS.md" ] || { echo "gpu_check: $out/RESULTS.md was not written" >&2; exit 1; }
# This device's run beside the repository's own quick run (lavapipe, PoCL and the cpu
# backend on the 2-core machine that made it): one document, a column per device.
baseline=bench/results-quick/results.json
if "$masq" report "$baseline" "$out/results.json" --label "$baseline=repository" --label "$out/results.json=$slug" \
    --out "$out/report" >/dev/null; then
  echo "gpu_check: beside the repository's quick run: $out/report/RESULTS.md"
else
  echo "gpu_check: no side-by-side report (the line above says why)"
fi
echo "gpu_check: done on '$device_name'; results in $out/RESULTS.md (and results.json beside it)"
