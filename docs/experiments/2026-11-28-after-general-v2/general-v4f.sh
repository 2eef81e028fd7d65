#!/usr/bin/env bash
# general v2 trained on at m: 256 updates (2,097,152 env steps) each, training seeds 1-3, then blended back into v2.
set -euo pipefail
k=.venv/bin/kinetix
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for s in 1 2 3; do
  date -u
  $k pretrain --config experiments/general.yaml --run-dir runs/general-v4f-seed$s --set env.size=m --set ppo.total_timesteps=2097152 --set run.init_from=general@2 --set run.eval_every=0 --set run.seed=$s --resume
  date -u
done
d=runs/general-v4f-blend
$k agents blend general@2 runs/general-v4f-seed1 runs/general-v4f-seed2 runs/general-v4f-seed3 --weight 3 --weight 1 --weight 1 --weight 1 -o $d --name general --version 3
$k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
for s in 1 2 3; do
  $k eval runs/general-v4f-seed$s "${held[@]}" --attempts 20 --seed 2000 --json runs/general-v4f-seed$s-heldout.json
done
echo ALLDONE
