#!/usr/bin/env bash
# general v2's recipe again with other training seeds for the three l runs (4, 5, 6; v2 used 1, 2, 3): does it hold?
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for s in 4 5 6; do
  date -u
  $k pretrain --config experiments/general.yaml --run-dir runs/general-v3l-seed$s --set env.size=l --set ppo.total_timesteps=2097152 --set run.init_from=general@1 --set run.eval_every=0 --set run.seed=$s --resume
  date -u
done
d=runs/general-v4g-seeds456
$k agents blend general-s@2 general@1 runs/general-v3l-seed4 runs/general-v3l-seed5 runs/general-v3l-seed6 --weight 3 --weight 3 --weight 2 --weight 2 --weight 2 -o $d --name general --version 3
$k eval $d "${paper[@]}" --attempts 50 --seed 1000 --json $d-paper-1000.json
$k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
echo ALLDONE
