#!/usr/bin/env bash
# `general` v3's recipe re-run whole from a new general-s base: v3's exact commands (the card of
# src/kinetix_cli/rl/shipped/general) with general-s v2's training seed 2 instead of 0 (seed 0 is general-s v2,
# seed 1 was gs-v2b, whose checkpoints are gone); everything downstream as v3 (m run seed 2, l runs seeds 1 2 3 6,
# weights 3:3:2:2:2:2). In-run evaluations off (run.eval_every=0): they do not touch training.
# 58 + 10 + 4 x ~12 = ~116 minutes of training, one job at a time.
set -euo pipefail
k=.venv/bin/kinetix
paper=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
held=(--levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l)
date -u
$k pretrain --config experiments/cpu-small.yaml --run-dir runs/general-v7-s --resume \
  --set env.size=s --set levels.source=fresh --set model.name=rel-mlp --set model.width=64 \
  --set model.mask_unused_actions=true --set env.dense_reward_scale=0.2 \
  --set ppo.num_envs=256 --set ppo.num_steps=32 --set ppo.total_timesteps=24000000 \
  --set curriculum.name=sfl --set curriculum.score_levels=384 --set curriculum.score_batch=128 \
  --set curriculum.score_steps=256 --set curriculum.score_attempts=2 --set curriculum.buffer_size=32 \
  --set curriculum.refresh_every=64 \
  --set run.checkpoint_every=125 --set run.eval_every=0 --set run.seed=2
date -u
$k pretrain --config experiments/general.yaml --run-dir runs/general-v7-m --resume --set env.size=m \
  --set ppo.total_timesteps=3276800 --set run.init_from=runs/general-v7-s --set run.eval_every=0 --set run.seed=2
date -u
for s in 1 2 3 6; do
  $k pretrain --config experiments/general.yaml --run-dir runs/general-v7-l-seed$s --resume --set env.size=l \
    --set ppo.total_timesteps=2097152 --set run.init_from=runs/general-v7-m --set run.eval_every=0 --set run.seed=$s
  date -u
done
d=runs/general-v7-blend
$k agents blend runs/general-v7-s runs/general-v7-m runs/general-v7-l-seed1 runs/general-v7-l-seed2 \
  runs/general-v7-l-seed3 runs/general-v7-l-seed6 --weight 3 --weight 3 --weight 2 --weight 2 --weight 2 --weight 2 \
  -o $d --name general --version 4
$k eval $d "${held[@]}" --attempts 20 --seed 2000 --json $d-heldout.json
$k eval $d "${paper[@]}" --attempts 50 --seed 1000 --json $d-paper-1000.json
$k eval $d "${paper[@]}" --attempts 50 --seed 1001 --json $d-paper-1001.json
date -u
echo ALLDONE
