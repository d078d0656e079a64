#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install what masq needs, build it, list the
# backends, and benchmark the embedded default scene (the masquerade paper's bundle of
# 1000 capsules, r=0.002, tilted 45 degrees, over a ground plane) on every backend and
# method. Extra arguments go to `masq bench` instead of the main job's own (--reps 3
# --warmup 0: the median of 3 timed traces per row, which also drops a cold first one, and
# auto's pilot at 3 rounds; `masq bench` alone warms up once and times 5), e.g.
# `--reps 5 --wide`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh masq   # only the command the main job runs, not the test binaries
./build/masq info
if [ $# -eq 0 ]; then set -- --reps 3 --warmup 0; fi
./build/masq bench "$@"
