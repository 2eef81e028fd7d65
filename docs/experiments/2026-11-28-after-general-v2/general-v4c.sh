#!/usr/bin/env bash
# Blends of general v2 with two of the three 128-update l runs (101 + 2 x 7.5 = ~116 min of training, within 2 hours).
set -euo pipefail
k=.venv/bin/kinetix
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
while ! grep -q ALLDONE runs/general-v4b.log; do sleep 20; done
for p in "1 2" "1 3" "2 3"; do
  set -- $p
  d=runs/general-v4c-$1$2
  $k agents blend general@2 runs/general-v4b-seed$1 runs/general-v4b-seed$2 --weight 2 --weight 1 --weight 1 -o $d --name general --version 3
  $k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
done
echo ALLDONE
