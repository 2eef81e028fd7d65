#!/usr/bin/env bash
# A third training seed of the 512-update l run from general v1 (seeds 21, 22 above): is seed 22's 24.5% the recipe's?
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
r=runs/general-v6l-seed23
date -u
$k pretrain --config experiments/general.yaml --run-dir $r --set env.size=l --set ppo.total_timesteps=4194304 --set run.minutes=25 --set run.init_from=general@1 --set run.eval_every=0 --set run.seed=23 --resume
date -u
$k eval $r "${paper[@]}" --attempts 50 --seed 1000 --json $r-paper-1000.json
$k eval $r "${held[@]}" --attempts 20 --seed 2000 --json $r-heldout.json
echo ALLDONE
