#!/usr/bin/env bash
# RERUN.md's check: 256 m levels with generate seed 204, solved as run.sh solves, in a fresh clone of main, alone.
# Run from the repository root: CLONE=<fresh clone, .venv built (make .venv/.installed-dev)> bash docs/experiments/2026-11-29-solved-sets/rerun.sh
set -euo pipefail
out=$PWD/docs/experiments/2026-11-29-solved-sets
cd "${CLONE:?a fresh clone of main, its .venv built (make .venv/.installed-dev)}"
echo "rerun at $(git rev-parse --short HEAD)"
kinetix=.venv/bin/kinetix
rm -rf runs/solved-sets/gen-m-204 runs/solved-sets/m-204
/usr/bin/time -f "%e s wall" -o "$out/rerun-generate-m-204.time" $kinetix generate --size m --count 256 --seed 204 \
  --out runs/solved-sets/gen-m-204 >"$out/rerun-generate-m-204.log" 2>&1
/usr/bin/time -f "%e s wall" -o "$out/rerun-solve-m-204.time" $kinetix levels solve runs/solved-sets/gen-m-204 \
  -o runs/solved-sets/m-204 --population 64 --iterations 10 --batch 64 --seed 0 >"$out/rerun-solve-m-204.log" 2>&1
$kinetix levels info runs/solved-sets/m-204 >"$out/rerun-info-m-204.txt" 2>&1
sed -n 2p "$out/rerun-info-m-204.txt"
