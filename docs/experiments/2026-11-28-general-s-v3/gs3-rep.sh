#!/usr/bin/env bash
# A second, unchosen draw of "general-s v2 + three continuations at s, blended with v2 at equal weights"
# (PLAN.md): the commands of gs3.sh with training seeds 4 5 6. One job at a time.
set -euo pipefail
k=.venv/bin/kinetix
date -u
for s in 4 5 6; do
  $k pretrain --config experiments/general.yaml --run-dir runs/gs3-seed$s --resume \
    --set ppo.total_timesteps=3276800 --set run.init_from=general-s@2 --set run.eval_every=0 --set run.seed=$s
  date -u
done
b=runs/gs3-blend4-rep
$k agents blend general-s@2 runs/gs3-seed4 runs/gs3-seed5 runs/gs3-seed6 -o $b --name general-s --version 3
for e in 1000 1001; do
  $k eval $b --levels .cache/reference-levels/s --attempts 50 --seed $e --json runs/gs3-blend4-rep-paper-$e.json
done
for e in 2000 2001; do
  $k eval $b --levels runs/heldout/s --attempts 50 --seed $e --json runs/gs3-blend4-rep-heldout-$e.json
done
date -u
echo ALLDONE
