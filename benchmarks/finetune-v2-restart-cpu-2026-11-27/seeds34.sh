#!/usr/bin/env bash
# issue 25: the restart rule with seeds it was not picked on: seeds 3 and 4 on rocket-car-jump and two-link-reach,
# the rule's arm (ft-v2-restart.sh) and scratch (general-s v2's network from scratch, the tables' settings).
set -euo pipefail
out=${OUT:-runs/ft-v2-seeds34}
levels="levels/s/rocket-car-jump.json levels/m/two-link-reach.json"
OUT=$out SEEDS="3 4" LEVELS="$levels" benchmarks/finetune-v2-restart-cpu-2026-11-27/ft-v2-restart.sh
for level in $levels; do
  name=$(basename "$level" .json)
  for seed in 3 4; do
    dir=$out/$name/scratch-$seed
    [ -f "$dir/eval.json" ] && continue
    rm -rf "$dir"
    .venv/bin/kinetix finetune "$level" --from none --run-dir "$dir" --config experiments/cpu-small.yaml \
      --set ppo.total_timesteps=200000 --set run.seed=$seed --set run.eval_every=25 \
      --set ppo.ent_coef=0.05 --set ppo.ent_coef_end=0.01 \
      --set model.name=rel-mlp --set model.width=64 --set model.mask_unused_actions=true
    .venv/bin/kinetix eval "$dir" --levels "$level" --attempts 50 --seed 1000 --json "$dir/eval.json"
  done
done
