#!/usr/bin/env bash
# A third, hand-made set that chose nothing: the project's own levels (levels/s, m, l; 60 levels): v3 and the seed-21 and seed-22 runs.
set -euo pipefail
k=.venv/bin/kinetix
own=(--levels levels/s --levels levels/m --levels levels/l)
$k eval general@3 "${own[@]}" --attempts 50 --seed 3000 --json runs/general-v6e-v3-own-3000.json
$k eval runs/general-v6l-seed22 "${own[@]}" --attempts 50 --seed 3000 --json runs/general-v6e-seed22-own-3000.json
$k eval runs/general-v6l-seed21 "${own[@]}" --attempts 50 --seed 3000 --json runs/general-v6e-seed21-own-3000.json
echo ALLDONE
