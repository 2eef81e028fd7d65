#!/usr/bin/env bash
# The shipped general v3 and v2 side by side at two more evaluation seeds on the 74 paper levels (1002, 1003):
# how much of v3's 22.0 / 22.1% (seeds 1000 / 1001) is attempt noise.
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
for seed in 1002 1003; do
  $k eval general@3 "${paper[@]}" --attempts 50 --seed $seed --json runs/general-v5d-v3-paper-$seed.json
  $k eval general@2 "${paper[@]}" --attempts 50 --seed $seed --json runs/general-v5d-v2-paper-$seed.json
done
echo ALLDONE
