#!/bin/bash
# The fig3 quick grid through ref, masq and auto on every backend (docs/methods.md,
# "The issue's target for auto"): prints backend, method, Mrays/s, isect/ray, B/prim
# per cell. Run from the repository root after building into ./build.
set -euo pipefail
cd "$(dirname "$0")/../build"
for nr in "10 0.01" "100 0.005" "1000 0.002"; do
  set -- $nr
  for tilt in 0 15 30 45; do
    echo "== N=$1 r=$2 tilt=$tilt"
    nice -n 15 ./masq bench --count "$1" --radius "$2" --tilt "$tilt" --ortho --backend cpu --backend vulkan \
      --backend opencl --backend rayquery --method ref --method masq --method auto --rays primary --width 256 \
      --height 256 --reps 3 --quiet --wide 2>&1 |
      grep -E "^(cpu|vulkan|opencl|rayquery) +(ref|masq|auto) +primary +[0-9]" | awk '{print $1, $2, $4, $9, $12}' || true
  done
done
