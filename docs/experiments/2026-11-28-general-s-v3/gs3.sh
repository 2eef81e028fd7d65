#!/usr/bin/env bash
# general-s v2 trained on at s for 400 updates (3,276,800 env steps) with its recipe, training seeds 1 2 3, and
# parameter averages of the runs with v2; every candidate evaluated on the held-out s levels (they choose, PLAN.md)
# and on the paper's s levels (reported, they do not choose). One job at a time.
set -euo pipefail
k=.venv/bin/kinetix
date -u
for s in 1 2 3; do
  $k pretrain --config experiments/general.yaml --run-dir runs/gs3-seed$s --resume \
    --set ppo.total_timesteps=3276800 --set run.init_from=general-s@2 --set run.eval_every=0 --set run.seed=$s
  date -u
done
$k agents blend runs/gs3-seed1 runs/gs3-seed2 runs/gs3-seed3 -o runs/gs3-blend3 --name general-s --version 3
$k agents blend general-s@2 runs/gs3-seed1 runs/gs3-seed2 runs/gs3-seed3 -o runs/gs3-blend4 --name general-s --version 3
for c in general-s@2 runs/gs3-seed1 runs/gs3-seed2 runs/gs3-seed3 runs/gs3-blend3 runs/gs3-blend4; do
  n=$(basename "$c")
  for e in 2000 2001; do
    $k eval "$c" --levels runs/heldout/s --attempts 50 --seed $e --json runs/gs3-$n-heldout-$e.json
  done
  for e in 1000 1001; do
    $k eval "$c" --levels .cache/reference-levels/s --attempts 50 --seed $e --json runs/gs3-$n-paper-$e.json
  done
  date -u
done
echo ALLDONE
