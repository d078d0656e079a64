#!/usr/bin/env bash
# Install what masq needs, build it and run the test suite (ctest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
# The loader fuzzers (clang, sanitizers) for ctest fuzz_smoke, built here with the rest
# so that the test runs them rather than compiling them.
if command -v clang++ >/dev/null; then BUILD=build/_fuzz bash scripts/fuzz.sh --build-only; fi
cd build
ctest --output-on-failure -j2 --timeout 900
