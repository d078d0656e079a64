#!/usr/bin/env bash
# Configures and builds masq into ./build (Release, Ninja). Arguments name the targets to
# build (default: all); scripts/main.sh builds only the masq command.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j"$(nproc)" "${targets[@]}"
