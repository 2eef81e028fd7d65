#!/usr/bin/env bash
# general-s v2 + general-m v2 (one lineage: general-s v2 then 60 min at l, 118 min of training): blends, held-out first.
set -euo pipefail
k=.venv/bin/kinetix
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
$k eval general-m@2 "${held[@]}" --attempts 20 --seed 2000 --json runs/general-m2-heldout.json
for w in "1 1" "1 2" "2 1" "1 3"; do
  set -- $w
  d=runs/general-v4a-$1-$2
  $k agents blend general-s@2 general-m@2 --weight $1 --weight $2 -o $d --name general --version 3
  $k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
done
echo ALLDONE
