#!/usr/bin/env bash
# More but shorter l runs in the same time: six 128-update runs at l from general v1 (training seeds 11-16) instead of
# v3's four 256-update runs, blended general-s v2 3 : general v1 3 : 4/3 each (the l runs' share as in v3, 8/14).
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
src=(); w=()
for s in 11 12 13 14 15 16; do
  date -u
  $k pretrain --config experiments/general.yaml --run-dir runs/general-v5e-seed$s --set env.size=l --set ppo.total_timesteps=1048576 --set run.init_from=general@1 --set run.eval_every=0 --set run.seed=$s --resume
  date -u
  src+=(runs/general-v5e-seed$s); w+=(--weight 4)
done
d=runs/general-v5e-six
$k agents blend general-s@2 general@1 "${src[@]}" --weight 9 --weight 9 "${w[@]}" -o $d --name general --version 4
$k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
$k eval $d "${paper[@]}" --attempts 50 --seed 1000 --json $d-paper-1000.json
echo ALLDONE
