#!/usr/bin/env bash
# general v3's recipe with its four 256-update l runs replaced by two longer ones (up to 512 updates, capped at
# 25 minutes each), training seeds 21, 22, from general v1; blend weights keep the l share (3 : 3 : 4 : 4).
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for s in 21 22; do
  date -u
  $k pretrain --config experiments/general.yaml --run-dir runs/general-v6l-seed$s --set env.size=l --set ppo.total_timesteps=4194304 --set run.minutes=25 --set run.init_from=general@1 --set run.eval_every=0 --set run.seed=$s --resume
  date -u
done
d=runs/general-v6b-two
$k agents blend general-s@2 general@1 runs/general-v6l-seed21 runs/general-v6l-seed22 --weight 3 --weight 3 --weight 4 --weight 4 -o $d --name general --version 4
$k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
$k eval $d "${paper[@]}" --attempts 50 --seed 1000 --json $d-paper-1000.json
$k eval $d "${paper[@]}" --attempts 50 --seed 1001 --json $d-paper-1001.json
echo ALLDONE
