#!/usr/bin/env bash
# general-s v2 seed 1 replication of candidate A (2026-11-26): the ablation's "all" recipe (rel-mlp 64, masking, dense 0.2, CPU-scale SFL), DR-style fresh s source, 256 envs
set -euo pipefail
.venv/bin/kinetix pretrain --config experiments/cpu-small.yaml --run-dir runs/gs-v2b \
  --set env.size=s --set levels.source=fresh --set model.name=rel-mlp --set model.width=64 \
  --set model.mask_unused_actions=true --set env.dense_reward_scale=0.2 \
  --set ppo.num_envs=256 --set ppo.num_steps=32 --set ppo.total_timesteps=24000000 \
  --set curriculum.name=sfl --set curriculum.score_levels=384 --set curriculum.score_batch=128 \
  --set curriculum.score_steps=256 --set curriculum.score_attempts=2 --set curriculum.buffer_size=32 \
  --set curriculum.refresh_every=64 \
  --set run.checkpoint_every=125 --set run.eval_every=500 --set run.eval_attempts=20 \
  --set 'run.eval_levels=[.cache/reference-levels/s]' --set run.seed=1
