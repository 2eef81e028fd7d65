#!/usr/bin/env bash
# A third draw of general-s v3's recipe (training seeds 7 8 9), run in a fresh clone of f6f9e3c (/tmp/fc, after
# make demo and make test there, .cache/reference-levels linked in) after v3 shipped; the paper's s levels only.
# Reported; it changes nothing shipped. 2026-11-28 12:32-12:51 UTC.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
k=.venv/bin/kinetix
date -u
for s in 7 8 9; do
  $k pretrain --config experiments/general.yaml --run-dir runs/gs3-seed$s --resume \
    --set ppo.total_timesteps=3276800 --set run.init_from=general-s@2 --set run.eval_every=0 --set run.seed=$s
  date -u
done
b=runs/gs3-blend4-rep2
$k agents blend general-s@2 runs/gs3-seed7 runs/gs3-seed8 runs/gs3-seed9 -o $b --name general-s --version 3
for e in 1000 1001; do
  $k eval $b --levels .cache/reference-levels/s --attempts 50 --seed $e --json runs/gs3-blend4-rep2-paper-$e.json
done
date -u
echo ALLDONE
