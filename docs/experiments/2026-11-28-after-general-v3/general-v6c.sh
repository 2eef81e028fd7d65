#!/usr/bin/env bash
# The runs behind the two blends above, each alone on the 74 paper levels (evaluation seed 1000).
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
for r in runs/general-v6l-seed21 runs/general-v6l-seed22 runs/general-v6m-seed1; do
  $k eval $r "${paper[@]}" --attempts 50 --seed 1000 --json $r-paper-1000.json
done
echo ALLDONE
