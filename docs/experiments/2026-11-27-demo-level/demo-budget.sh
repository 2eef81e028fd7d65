#!/usr/bin/env bash
# issue 25, demo rework: general-s v2 fine-tuned with a fresh policy head vs scratch (same network) at small budgets,
# evaluated every 5 updates (10,240 steps) with 20 attempts; 3 seeds; cpu-small with entropy 0.05 -> 0.01 in both arms
set -euo pipefail
for level in rocket-car-jump aim-then-fire; do
  for seed in 0 1 2; do
    for arm in fresh-head scratch; do
      dir=runs/demo-budget/$level/$arm-$seed
      [ -f "$dir/eval.json" ] && continue
      rm -rf "$dir"
      if [ $arm = scratch ]; then
        from=(--from none --set model.name=rel-mlp --set model.width=64 --set model.mask_unused_actions=true)
      else
        from=(--from general-s --set run.fresh_policy_head=true)
      fi
      .venv/bin/kinetix finetune levels/s/$level.json "${from[@]}" --run-dir "$dir" --config experiments/cpu-small.yaml \
        --set ppo.total_timesteps=81920 --set run.seed=$seed --set run.eval_every=5 \
        --set ppo.ent_coef=0.05 --set ppo.ent_coef_end=0.01
      .venv/bin/kinetix eval "$dir" --levels levels/s/$level.json --attempts 50 --seed 1000 --json "$dir/eval.json"
    done
  done
done
