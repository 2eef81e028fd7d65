#!/usr/bin/env bash
# A second evaluation seed for the held-out winner (general-v3c-withs) and general v1.
set -euo pipefail
cd "$(dirname "$0")/../.."
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
$k eval runs/general-v3c-withs "${held[@]}" --attempts 20 --seed 2001 --json runs/general-v3c-withs-heldout-2001.json
$k eval general@1 "${held[@]}" --attempts 20 --seed 2001 --json runs/general-v1-heldout-2001.json
$k eval runs/general-v3c-withs "${paper[@]}" --attempts 50 --seed 1001 --json runs/general-v3c-withs-paper-1001.json
echo ALLDONE
