#!/usr/bin/env bash
# The validation suite's held-out levels searched as lever 2's solved sets were (2026-11-29-solved-sets/run.sh's
# settings): the sets rebuilt from the suite's seeds, then `kinetix levels solve` per size, timed, then `levels info`.
# Run from the checkout's root, alone: bash docs/experiments/2026-11-30-validation-signal/run.sh
set -euo pipefail
out=docs/experiments/2026-11-30-validation-signal
kinetix=.venv/bin/kinetix
.venv/bin/python $out/heldout_sets.py runs/validation-sets >$out/heldout_sets.log 2>&1
for size in s m l; do
  [ -d "runs/validation-solved/$size" ] || /usr/bin/time -f "%e s wall" -o "$out/solve-$size.time" $kinetix levels \
    solve "runs/validation-sets/$size" -o "runs/validation-solved/$size" --population 64 --iterations 10 --batch 64 \
    --seed 0 >"$out/solve-$size.log" 2>&1
  $kinetix levels info "runs/validation-solved/$size" >"$out/info-$size.txt" 2>&1
done
