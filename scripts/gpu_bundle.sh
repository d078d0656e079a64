#!/usr/bin/env bash
# Builds the GPU bundle: one relocatable folder (and a .tar.gz of it) holding masq, the
# test binaries the GPU run needs, every shared library they load but glibc (the Vulkan
# loader and the OpenCL ICD loader among them) under $ORIGIN, the scene files and the
# repository's quick results to compare with, and run.sh (scripts/gpu_run.sh), which
# runs the whole GPU check there: a GPU machine needs no package and no network.
# docs/devices.md, "The GPU bundle", says how a run is carried and what comes back.
#
#   bash scripts/gpu_bundle.sh                    set up, build build-gpu (x86-64-v3, no Embree, no
#                                                 image output, no Python) and bundle it into
#                                                 gpu-bundle/masq-gpu (+ gpu-bundle/masq-gpu.tar.gz)
#   bash scripts/gpu_bundle.sh --no-setup         skip scripts/setup.sh
#   bash scripts/gpu_bundle.sh --from-build DIR --out DIR
#                                                 bundle an existing build instead (the sealed
#                                                 test's: ctest gpu_bundle_sealed), no archive
#
# On the GPU machine: tar xzf masq-gpu.tar.gz && masq-gpu/run.sh OUTDIR
#
# libstdc++ and libgcc_s: the binaries need Debian 12's (GCC 12) or newer. A GPU driver's
# own libraries may need a newer one, which two copies in one process would break, so
# the bundle's copies sit apart in lib/fallback with the symbol versions the bundle
# needs (lib/fallback/NEEDS); run.sh uses the system's where it has every one of them
# and the bundle's only where it does not (an older or a bare system).
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; }

setup=1 from_build="" out=gpu-bundle
while [ $# -gt 0 ]; do
  case "$1" in
    --no-setup) setup=0; shift ;;
    --from-build) [ $# -ge 2 ] || { echo "gpu_bundle: --from-build needs a folder" >&2; exit 2; }; from_build=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || { echo "gpu_bundle: --out needs a folder" >&2; exit 2; }; out=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "gpu_bundle: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done

# The binaries the run uses (scripts/gpu_run.sh).
targets=(masq test_cross_backend test_occlusion test_node_formats_cross test_traversal_faults test_device_choice)
# The scene files it reads, relative to ../shared/data, with their licences.
data_files=(hair/tressfx3_bear.tfx licenses)
# glibc's own libraries stay the system's (every Linux has them, and they must match its
# dynamic loader).
glibc='^(linux-vdso\.so|ld-linux-x86-64\.so|libc\.so|libm\.so|libpthread\.so|libdl\.so|librt\.so|libresolv\.so|libutil\.so|libmvec\.so)'
# The C++ runtime: system's when new enough, else the bundle's (see the top).
cxx_runtime='^(libstdc\+\+\.so|libgcc_s\.so)'
# What NVIDIA's Vulkan ICD (libGLX_nvidia.so.0) loads but GPU containers may lack: GLVND
# (its dispatch, GLX, EGL, GL, OpenGL and GLES front ends, the set a GPU lease's notes
# name for Vulkan there), libdrm, and the X11 client libraries under them. Without them
# the loader finds the ICD but vkCreateInstance is refused (VK_ERROR_INCOMPATIBLE_DRIVER,
# docs/results.md). run.sh puts on the library path only those the machine lacks.
driver_support=(libGLdispatch.so.0 libGLX.so.0 libEGL.so.1 libGL.so.1 libOpenGL.so.0 libGLESv2.so.2 libdrm.so.2
                libX11.so.6 libXext.so.6 libxcb.so.1 libXau.so.6 libXdmcp.so.6 libbsd.so.0 libmd.so.0)

if [ -z "$from_build" ]; then
  [ $setup -eq 1 ] && bash scripts/setup.sh
  build=build-gpu
  # x86-64-v3 (AVX2, FMA; contraction stays off: CMakeLists.txt) runs on every GPU host
  # of the last decade; Embree, OpenImageIO and the Python module are not needed there.
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMASQ_NATIVE_ISA=OFF -DCMAKE_CXX_FLAGS=-march=x86-64-v3 \
    -DMASQ_WITH_IMAGES=OFF -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON -DCMAKE_DISABLE_FIND_PACKAGE_pybind11=ON >/dev/null
  cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"
else
  build=$from_build
fi
for t in "${targets[@]}"; do
  f="$build/$t"; [ -x "$f" ] || f="$build/tests/$t"
  [ -x "$f" ] || { echo "gpu_bundle: $t is not built in $build" >&2; exit 1; }
done
for tool in patchelf ldd strip; do
  command -v "$tool" >/dev/null || { echo "gpu_bundle: $tool not found (scripts/setup.sh installs it)" >&2; exit 1; }
done

root="$out/masq-gpu"
rm -rf "$root"
mkdir -p "$root/bin" "$root/lib/fallback" "$root/lib/driver" "$root/data" "$root/baseline"

# Binaries, stripped, finding their libraries in ../lib.
for t in "${targets[@]}"; do
  f="$build/$t"; [ -x "$f" ] || f="$build/tests/$t"
  cp "$f" "$root/bin/$t"
  strip --strip-unneeded "$root/bin/$t"
  patchelf --set-rpath '$ORIGIN/../lib' "$root/bin/$t"
done

# Every library they load, transitively, but glibc's: ldd resolves the whole closure.
declare -A copied=()
for b in "$root"/bin/*; do
  while read -r name path; do
    [ -n "$path" ] || continue
    [[ $name =~ $glibc ]] && continue
    [ -n "${copied[$name]:-}" ] && continue
    copied[$name]=1
    if [[ $name =~ $cxx_runtime ]]; then dest="$root/lib/fallback/$name"; else dest="$root/lib/$name"; fi
    cp -L "$path" "$dest"
    chmod u+w "$dest"
    strip --strip-unneeded "$dest" 2>/dev/null || true
    patchelf --set-rpath '$ORIGIN' "$dest"
  done < <(ldd "$b" | awk '$2 == "=>" && $3 ~ /^\// { print $1, $3 }')
done
for name in "${driver_support[@]}"; do
  path=$(ldconfig -p | awk -v n="$name" '$1 == n && /x86-64/ && !found { found = 1; print $NF }')
  if [ -z "$path" ]; then
    echo "gpu_bundle: $name not found (scripts/setup.sh installs it: libglvnd0, libglx0, libegl1, libgl1, libopengl0, libgles2, libdrm2, libx11-6, libxext6)" >&2
    exit 1
  fi
  cp -L "$path" "$root/lib/driver/$name"
  chmod u+w "$root/lib/driver/$name"
  strip --strip-unneeded "$root/lib/driver/$name" 2>/dev/null || true
  patchelf --set-rpath '$ORIGIN' "$root/lib/driver/$name"
done
# The symbol versions of the C++ runtime that the bundle's objects need: run.sh keeps the
# system's runtime only where it provides every one.
objdump -T "$root"/bin/* "$root"/lib/*.so* 2>/dev/null |
  grep -oE '\b(GLIBCXX|CXXABI|GCC)_[0-9.]+\b' | sort -u >"$root/lib/fallback/NEEDS"

# Scenes and licences; the repository's quick results for `masq report`.
data_root=${MASQ_DATA:-../shared/data}
for f in "${data_files[@]}"; do
  [ -e "$data_root/$f" ] || { echo "gpu_bundle: $data_root/$f not found (../shared/data beside the checkout)" >&2; exit 1; }
  mkdir -p "$root/data/$(dirname "$f")"
  cp -r "$data_root/$f" "$root/data/$f"
done
cp bench/results-quick/results.json "$root/baseline/results.json"
cp scripts/gpu_run.sh "$root/run.sh"
chmod +x "$root/run.sh"
{
  echo "masq GPU bundle"
  echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet HEAD 2>/dev/null || echo ' (with uncommitted changes)')"
  echo "built: $(date -u +%Y-%m-%dT%H:%MZ) on $(uname -m), from $build"
  echo "compiler flags: $(grep -m1 '^CMAKE_CXX_FLAGS:' "$build/CMakeCache.txt" | cut -d= -f2-) (MASQ_NATIVE_ISA=$(grep -m1 '^MASQ_NATIVE_ISA:' "$build/CMakeCache.txt" | cut -d= -f2-))"
  echo "libraries: $(cd "$root/lib" && ls | grep -v 'fallback\|driver' | tr '\n' ' ')"
  echo "driver support (used where the machine lacks them): $(cd "$root/lib/driver" && ls | tr '\n' ' ')"
  echo "fallback C++ runtime: $(cd "$root/lib/fallback" && ls | grep -v NEEDS | tr '\n' ' ')"
} >"$root/BUILD_INFO"

bytes=$(du -sb "$root" | cut -f1)
echo "gpu_bundle: $root: $(( bytes / 1024 / 1024 )) MiB, $(ls "$root/lib" | grep -vc 'fallback\|driver') libraries"
if [ -z "$from_build" ]; then
  tar -C "$out" -czf "$out/masq-gpu.tar.gz" masq-gpu
  archive=$(du -b "$out/masq-gpu.tar.gz" | cut -f1)
  repo=$(git ls-files -z | xargs -0 du -cb 2>/dev/null | tail -1 | cut -f1)
  echo "gpu_bundle: $out/masq-gpu.tar.gz: $(( archive / 1024 / 1024 )) MiB; with the repository's $(( repo / 1024 / 1024 )) MiB: $(( (archive + repo) / 1024 / 1024 )) MiB"
  if [ $(( archive + repo )) -gt $(( 56 * 1024 * 1024 )) ]; then
    echo "gpu_bundle: the bundle and the repository exceed 56 MiB (a GPU machine takes at most 64 MiB)" >&2
    exit 1
  fi
  echo "gpu_bundle: carry $out/masq-gpu.tar.gz; there: tar xzf masq-gpu.tar.gz && masq-gpu/run.sh OUTDIR"
fi
