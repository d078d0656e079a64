#!/usr/bin/env bash
# Merges several bench runs into one document and draws its plots (docs/bench.md,
# "Several machines and devices: masq report").
#   bash scripts/report.sh runs/*/results.json --out report
# Arguments go to `masq report` (--out DIR, default report; --label FILE=NAME); paths are
# relative to where it is called from. Uses the repository's build/masq (scripts/build.sh).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out=report
args=("$@")
for ((i = 0; i < ${#args[@]}; ++i)); do
  if [ "${args[i]}" = "--out" ] && [ $((i + 1)) -lt ${#args[@]} ]; then out=${args[i + 1]}; fi
done
"$repo/build/masq" report "$@"
/usr/bin/python3 "$repo/scripts/plot_report.py" "$out"
