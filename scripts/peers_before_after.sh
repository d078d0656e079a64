#!/usr/bin/env bash
# The peers suite (masq against Embree) of an earlier commit and of this checkout, run
# back to back on this machine and merged into one table, row by row (docs/bench.md,
# "Before and after"):
#   bash scripts/peers_before_after.sh REV [OUT]
# REV is checked out as a worktree in build/before-REV and its masq command built there;
# this checkout's by scripts/build.sh. Both suites run in full on the cpu and OpenCL
# backends, REV's first: OUT/before and OUT/after hold their own RESULTS.md, OUT/RESULTS.md
# the merge (masq report). OUT defaults to peers-REV-vs-HEAD. Scenes: $MASQ_DATA, else
# ../shared/data beside the repository.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: bash scripts/peers_before_after.sh REV [OUT]" >&2
  exit 2
fi
rev=$(git -C "$repo" rev-parse --short "$1^{commit}") # an unknown REV stops here, in git's words
head=$(git -C "$repo" describe --always --dirty)
out=${2:-peers-$rev-vs-$head}
data=${MASQ_DATA:-$repo/../shared/data}
tree=$repo/build/before-$rev
[ -d "$tree" ] || git -C "$repo" worktree add --detach "$tree" "$rev"
cmake -S "$tree" -B "$tree/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tree/build" -j"$(nproc)" --target masq
bash "$repo/scripts/build.sh" masq
mkdir -p "$out"
"$tree/build/masq" bench --suite peers --backend cpu opencl --data "$data" --out "$out/before"
"$repo/build/masq" bench --suite peers --backend cpu opencl --data "$data" --out "$out/after"
"$repo/build/masq" report "$out/before/results.json" "$out/after/results.json" --out "$out" \
  --label "$out/before/results.json=$rev" --label "$out/after/results.json=$head"
