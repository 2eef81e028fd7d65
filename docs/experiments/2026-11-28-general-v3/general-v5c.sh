#!/usr/bin/env bash
# How much of general-v5a-plus6's score is its recipe and how much its draw: the same blend (general-s v2, general v1,
# four 256-update l runs from v1; weights 3:3:2:2:2:2) for every 4 of the six l runs trained so far (seeds 1-3 by
# general v2's card, 4-6 by general-v4g.sh), scored on the 74 paper levels (seed 1000) and the held-out set (seed 2000).
# Run after the shipped agent was chosen (general-v5a.sh, held-out only), so none of this chose it.
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for q in 1234 1235 1236 1245 1246 1256 1345 1346 1356 1456 2345 2346 2356 2456 3456; do
  d=runs/general-v5c-$q
  src=(); w=()
  for c in $(echo $q | grep -o .); do src+=(runs/general-v3l-seed$c); w+=(--weight 2); done
  [ -d $d ] || $k agents blend general-s@2 general@1 "${src[@]}" --weight 3 --weight 3 "${w[@]}" -o $d --name general --version 3
  [ -f $d-paper-1000.json ] || $k eval $d "${paper[@]}" --attempts 50 --seed 1000 --json $d-paper-1000.json
  [ -f $d-heldout.json ] || $k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
done
echo ALLDONE
