#!/usr/bin/env bash
# general v2 trained on at l: 128 updates (1,048,576 env steps, ~5.5 min) each, training seeds 1-3 (101 + 3 x 5.5 = ~118 min in all).
set -euo pipefail
k=.venv/bin/kinetix
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
for s in 1 2 3; do
  date -u
  $k pretrain --config experiments/general.yaml --run-dir runs/general-v4b-seed$s --set env.size=l --set ppo.total_timesteps=1048576 --set run.init_from=general@2 --set run.eval_every=0 --set run.seed=$s --resume
  date -u
done
for s in 1 2 3; do
  $k eval runs/general-v4b-seed$s "${held[@]}" --attempts 20 --seed 2000 --json runs/general-v4b-seed$s-heldout.json
done
for w in "1 1" "3 1"; do
  set -- $w
  d=runs/general-v4b-blend-$1-$2
  $k agents blend general@2 runs/general-v4b-seed1 runs/general-v4b-seed2 runs/general-v4b-seed3 --weight $(( $1 * 3 )) --weight $2 --weight $2 --weight $2 -o $d --name general --version 3
  $k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
done
echo ALLDONE
