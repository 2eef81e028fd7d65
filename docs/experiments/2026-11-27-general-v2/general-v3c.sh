#!/usr/bin/env bash
# Two more blends: general v1 at 2/3 with its three l runs at 1/9 each; general-s v2 and v1 at 1/4 each with the
# three l runs at 1/6 each. Evaluated on both sets.
set -euo pipefail
cd "$(dirname "$0")/../.."
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
l=(runs/general-v3l-seed1 runs/general-v3l-seed2 runs/general-v3l-seed3)
$k agents blend general@1 "${l[@]}" --weight 6 --weight 1 --weight 1 --weight 1 -o runs/general-v3c-twothirds --name general --version 2
$k agents blend general-s@2 general@1 "${l[@]}" --weight 3 --weight 3 --weight 2 --weight 2 --weight 2 -o runs/general-v3c-withs --name general --version 2
for p in runs/general-v3c-twothirds runs/general-v3c-withs; do
  $k eval $p "${held[@]}" --attempts 20 --seed 2000 --json $p-heldout.json
  $k eval $p "${paper[@]}" --attempts 50 --seed 1000 --json $p-paper-1000.json
done
echo ALLDONE
