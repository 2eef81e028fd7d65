#!/usr/bin/env bash
# general v2's five sources, other weights (a pre-set grid; v2 is 3 3 2 2 2): held-out seed 2000 first.
set -euo pipefail
k=.venv/bin/kinetix
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for w in "2 1 1 1 1" "1 2 1 1 1" "3 3 1 1 1" "1 1 1 1 1"; do
  set -- $w
  d=runs/general-v4d-$1$2$3$4$5
  $k agents blend general-s@2 general@1 runs/general-v3l-seed1 runs/general-v3l-seed2 runs/general-v3l-seed3 --weight $1 --weight $2 --weight $3 --weight $4 --weight $5 -o $d --name general --version 3
  $k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
done
echo ALLDONE
