#!/usr/bin/env bash
# Regenerates the benchmark results document with one command: builds masq, runs every
# bench suite (fig3, table1, table2, fig9, fig10, error, peers) on every backend, and
# draws the plots beside it.
#   bash scripts/results.sh           full run  -> bench/results/RESULTS.md  (< 30 min on 2 cores before the
#                                     peers suite traced every tracer on o4 nodes too; not re-measured since)
#   bash scripts/results.sh --quick   quick run -> bench/results-quick/RESULTS.md  (29 min on an idle 2-core machine at 8f21c51, the peers suite 16 min; 55 min when other work shared the cores: every tracer on w4 and o4 nodes, rayquery and rtpipeline beside)
# Extra arguments go to `masq bench` (e.g. --backend cpu --backend opencl).
set -euo pipefail
cd "$(dirname "$0")/.."
out=bench/results
if [ "${1:-}" = "--quick" ]; then
  out=bench/results-quick
fi
bash scripts/setup.sh
bash scripts/build.sh
./build/masq bench --suite all --out "$out" "$@"
/usr/bin/python3 scripts/plot_results.py "$out"
