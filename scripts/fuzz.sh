#!/usr/bin/env bash
# Builds the libFuzzer targets (one per loader, fuzz/) with clang into build-fuzz/ and
# runs each for RUNS executions (default 15000: 9 targets x 15000 = 135,000 in all),
# starting from hand-made seeds (fuzz/make_seeds.py) plus the kept regression inputs
# (tests/fuzz_regressions/<format>/). A crash leaves its input in build-fuzz/findings/
# and makes the script fail; fix the loader, then copy the input into
# tests/fuzz_regressions/<format>/ so test_fuzz_regressions replays it forever.
#   bash scripts/fuzz.sh                 # all formats, 15000 runs each
#   RUNS=1000000 bash scripts/fuzz.sh ply obj   # longer, chosen formats
#   bash scripts/fuzz.sh --build-only    # build the targets, run nothing (scripts/test.sh,
#                                        # so that ctest fuzz_smoke only fuzzes)
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${RUNS:-15000}
BUILD=${BUILD:-build-fuzz}
build_only=0
if [ "${1:-}" = --build-only ]; then build_only=1; shift; fi
formats=("$@")
[ ${#formats[@]} -gt 0 ] || formats=(tfx hair swc trk tck ply obj nff json)

command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (bash scripts/setup.sh installs it)" >&2; exit 1; }
CC=clang CXX=clang++ cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMASQ_FUZZ=ON \
  -DMASQ_BUILD_TESTS=OFF >/dev/null
nice -n 15 cmake --build "$BUILD" -j2 --target fuzz_all
[ "$build_only" = 0 ] || exit 0

python3 fuzz/make_seeds.py "$BUILD/seeds"
mkdir -p "$BUILD/findings"
total=0
status=0
for f in "${formats[@]}"; do
  corpus="$BUILD/corpus/$f"
  mkdir -p "$corpus"
  extra=()
  [ -d "tests/fuzz_regressions/$f" ] && extra+=("tests/fuzz_regressions/$f")
  log="$BUILD/findings/$f.log"
  # -timeout: a loader taking > 10 s on an input of <= 4 KiB is a finding (a hang).
  if nice -n 15 "$BUILD/fuzz/fuzz_$f" "$corpus" "$BUILD/seeds/$f" "${extra[@]}" -runs="$RUNS" -max_len=4096 \
      -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$BUILD/findings/$f-" >"$log" 2>&1; then
    done_runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
    total=$((total + done_runs))
    echo "fuzz $f: $done_runs executions, no findings"
  else
    status=1
    echo "fuzz $f: FINDING (see $log and $BUILD/findings/$f-*)"
    grep -m3 -E 'ERROR|SUMMARY|runtime error' "$log" || tail -5 "$log"
  fi
done
echo "fuzz: $total executions in all"
exit $status
