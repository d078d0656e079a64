#!/usr/bin/env bash
# Installs masq from BUILD_DIR into BUILD_DIR/_install, then configures, builds and runs
# examples/consumer against it with find_package(masq) (a ctest test: consumer_package).
set -euo pipefail
build=$1
src=$2
prefix="$build/_install"
rm -rf "$prefix" "$build/_consumer"
cmake --install "$build" --prefix "$prefix" >/dev/null
cmake -S "$src/examples/consumer" -B "$build/_consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$build/_consumer"
"$build/_consumer/consumer" cpu
