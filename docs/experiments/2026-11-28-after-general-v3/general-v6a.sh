#!/usr/bin/env bash
# general v3 (~114 min of training) trained on for 128 updates (1,048,576 env steps, 2.6 min each as run) at size m,
# training seeds 1-3; each alone and blended with v3 (1:1, 3:1), scored on the 120 held-out levels.
set -euo pipefail
k=.venv/bin/kinetix
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for s in 1 2 3; do
  r=runs/general-v6m-seed$s
  date -u
  $k pretrain --config experiments/general.yaml --run-dir $r --set env.size=m --set ppo.total_timesteps=1048576 --set run.init_from=general@3 --set run.eval_every=0 --set run.seed=$s --resume
  date -u
  $k eval $r "${held[@]}" --attempts 20 --seed 2000 --json $r-heldout.json
  for w in 1 3; do
    b=runs/general-v6m-seed$s-blend$w
    $k agents blend general@3 $r --weight $w --weight 1 -o $b --name general --version 4
    $k eval $b "${held[@]}" --attempts 20 --seed 2000 --json $b-heldout.json
  done
done
echo ALLDONE
