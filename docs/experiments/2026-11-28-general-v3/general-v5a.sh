#!/usr/bin/env bash
# general v2's five sources plus one more 256-update l run from v1 (training seed 4, 5 or 6, trained by general-v4g.sh):
# 58 + 10 + 3 x 11 + 12.6-14.7 = 114-116 minutes of training, inside the 2-hour rule. Weights 3:3:2:2:2:2.
set -euo pipefail
k=.venv/bin/kinetix
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for s in 4 5 6; do
  d=runs/general-v5a-plus$s
  $k agents blend general-s@2 general@1 runs/general-v3l-seed1 runs/general-v3l-seed2 runs/general-v3l-seed3 runs/general-v3l-seed$s \
    --weight 3 --weight 3 --weight 2 --weight 2 --weight 2 --weight 2 -o $d --name general --version 3
  $k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
done
echo ALLDONE
