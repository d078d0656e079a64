#!/usr/bin/env bash
# Installs every Debian package masq needs. Idempotent: safe to run again.
# Mesa (lavapipe with VK_KHR_ray_query) comes from bookworm-backports; the apt source
# for it is derived from the system's own debian.sources (same URIs and key), so no
# registry host is written into this repository.
set -euo pipefail

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive

main_sources=/etc/apt/sources.list.d/debian.sources
backports_sources=/etc/apt/sources.list.d/masq-bookworm-backports.sources

add_backports_source() {
  if [ -f "$backports_sources" ]; then return; fi
  if [ ! -f "$main_sources" ]; then
    echo "setup: $main_sources not found; cannot derive the bookworm-backports source" >&2
    exit 1
  fi
  # Copy the stanza whose Suites list contains 'bookworm' (the main archive, not
  # security) and replace its Suites line with bookworm-backports.
  awk -v RS= '
    /(^|\n)Suites:[^\n]*(^|[ \t])bookworm([ \t]|\n|$)/ && !done {
      n = split($0, lines, "\n")
      for (i = 1; i <= n; i++) {
        if (lines[i] ~ /^Suites:/) printf "Suites: bookworm-backports\n"
        else if (lines[i] !~ /^#/) printf "%s\n", lines[i]
      }
      done = 1
    }' "$main_sources" | $SUDO tee "$backports_sources.tmp" >/dev/null
  if ! grep -q '^Suites: bookworm-backports' "$backports_sources.tmp"; then
    echo "setup: no bookworm stanza in $main_sources to derive backports from" >&2
    $SUDO rm -f "$backports_sources.tmp"
    exit 1
  fi
  $SUDO mv "$backports_sources.tmp" "$backports_sources"
}

packages=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev vulkan-tools vulkan-validationlayers glslang-tools spirv-tools
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  libglm-dev libgtest-dev libgmock-dev libbenchmark-dev
  libopenimageio-dev libcli11-dev libfmt-dev nlohmann-json3-dev libtinyobjloader-dev libembree-dev libtbb-dev
  python3-matplotlib python3-numpy python3-dev pybind11-dev python3-pytest
  python3-venv python3-pip # pip install . into a virtual environment (tests/python_pip_install.sh)
  python3-mypy            # stubgen and stubtest: the Python stubs (ctest python_stub, python_stubtest)
  clang libclang-rt-dev doxygen
  patchelf busybox-static # the GPU bundle's $ORIGIN paths and its sealed test's shell (scripts/gpu_bundle.sh)
  libglvnd0 libglx0 libegl1 libgl1 libopengl0 libgles2 libdrm2 libx11-6 libxext6 # the bundle carries them for NVIDIA's Vulkan ICD
  valgrind                # the kernels' memcheck runs (ctest kernels_memcheck_*)
  fonts-dejavu-core       # the heatmaps' colour-bar labels (OpenImageIO's render_text)
)

need_install=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    need_install+=("$p")
  fi
done

mesa_ok() {
  local v
  v=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
  [ -n "$v" ] && dpkg --compare-versions "$v" ge 24.1
}

skbuild_ok() { dpkg-query -W -f='${Status}' python3-scikit-build-core 2>/dev/null | grep -q 'install ok installed'; }

add_backports_source
if [ ${#need_install[@]} -gt 0 ] || ! mesa_ok || ! skbuild_ok; then
  $SUDO apt-get update -q
fi
if [ ${#need_install[@]} -gt 0 ]; then
  $SUDO apt-get install -y -q --no-install-recommends "${need_install[@]}"
fi
if ! mesa_ok; then
  $SUDO apt-get install -y -q --no-install-recommends -t bookworm-backports mesa-vulkan-drivers
fi
mesa_ok || { echo "setup: mesa-vulkan-drivers >= 24.1 could not be installed" >&2; exit 1; }
# pyproject.toml's build backend: bookworm has no scikit-build-core, bookworm-backports
# has it (with the newer python3-packaging it needs, hence -t).
if ! skbuild_ok; then
  $SUDO apt-get install -y -q --no-install-recommends -t bookworm-backports python3-scikit-build-core
fi
echo "setup: all packages present (mesa-vulkan-drivers $(dpkg-query -W -f='${Version}' mesa-vulkan-drivers))"
