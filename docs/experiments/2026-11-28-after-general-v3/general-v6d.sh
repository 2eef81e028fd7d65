#!/usr/bin/env bash
# After the paper-level look: the two 512-update l runs alone on the held-out set, and seed 22 at paper seeds 1001-1003.
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for s in 21 22; do
  $k eval runs/general-v6l-seed$s "${held[@]}" --attempts 20 --seed 2000 --json runs/general-v6l-seed$s-heldout.json
done
for e in 1001 1002 1003; do
  $k eval runs/general-v6l-seed22 "${paper[@]}" --attempts 50 --seed $e --json runs/general-v6l-seed22-paper-$e.json
done
echo ALLDONE
