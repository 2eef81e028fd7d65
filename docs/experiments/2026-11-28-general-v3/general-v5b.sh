#!/usr/bin/env bash
# The best of general-v5a.sh on the held-out set (plus seed 6, 23.3% vs v2's 23.1%), checked at held-out seed 2001
# and on the 74 paper levels at evaluation seeds 1000 and 1001.
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
d=runs/general-v5a-plus6
$k eval $d "${held[@]}" --attempts 20 --seed 2001 --json $d-heldout-2001.json
$k eval $d "${paper[@]}" --attempts 50 --seed 1000 --json $d-paper-1000.json
$k eval $d "${paper[@]}" --attempts 50 --seed 1001 --json $d-paper-1001.json
echo ALLDONE
