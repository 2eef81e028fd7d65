#!/usr/bin/env bash
# The paper levels for the best new held-out candidates (not for choosing: to see whether held-out tracks the paper levels).
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
for d in runs/general-v4b-blend-3-1 runs/general-v4d-21111; do
  $k eval $d "${paper[@]}" --attempts 50 --seed 1000 --json $d-paper-1000.json
done
echo ALLDONE
