#!/usr/bin/env bash
# Two more blends of general v1 with its three l runs (general-v3l.sh), evaluated on both sets.
set -euo pipefail
cd "$(dirname "$0")/../.."
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
l=(runs/general-v3l-seed1 runs/general-v3l-seed2 runs/general-v3l-seed3)
$k agents blend general@1 "${l[@]}" --weight 3 --weight 1 --weight 1 --weight 1 -o runs/general-v3b-half --name general --version 2
$k agents blend general@1 "${l[@]}" -o runs/general-v3b-equal --name general --version 2
for p in runs/general-v3b-half runs/general-v3b-equal; do
  $k eval $p "${held[@]}" --attempts 20 --seed 2000 --json $p-heldout.json
  $k eval $p "${paper[@]}" --attempts 50 --seed 1000 --json $p-paper-1000.json
done
echo ALLDONE
