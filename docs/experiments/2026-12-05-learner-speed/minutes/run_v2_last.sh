#!/bin/bash
# v2's own code for another seed (README.md, "v2's own code, another seed's last checkpoints"): general-s v2's
# command on 720f386 (a worktree on PYTHONPATH, checkpoint retention raised from 3 to 100; nothing else changed) for
# training seed $1, then its last three checkpoints on the validation suite with today's `kinetix validation`. Runs
# in /tmp/minutes; metrics and scores land next to this script.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/minutes
OUT=/tmp/minutes
SEED=${1:?training seed}
K=.venv/bin/kinetix
if [ ! -d /tmp/wt-v2 ]; then
  git worktree add --detach /tmp/wt-v2 720f386
  sed -i 's/^KEEP = 3/KEEP = 100/' /tmp/wt-v2/src/kinetix_cli/rl/checkpoints.py
fi
echo "== code $(git -C /tmp/wt-v2 rev-parse HEAD) + $(git -C /tmp/wt-v2 diff --stat | tail -1)"
mkdir -p $OUT
run=$OUT/v2-$SEED
echo "== train $SEED $(date -u +%T)"
PYTHONPATH=/tmp/wt-v2/src $K pretrain --config /tmp/wt-v2/experiments/cpu-small.yaml --run-dir $run \
  --set env.size=s --set levels.source=fresh --set model.name=rel-mlp --set model.width=64 \
  --set model.mask_unused_actions=true --set env.dense_reward_scale=0.2 --set ppo.num_envs=256 \
  --set ppo.num_steps=32 --set ppo.total_timesteps=24000000 --set curriculum.name=sfl \
  --set curriculum.score_levels=384 --set curriculum.score_batch=128 --set curriculum.score_steps=256 \
  --set curriculum.score_attempts=2 --set curriculum.buffer_size=32 --set curriculum.refresh_every=64 \
  --set run.checkpoint_every=256 --set run.eval_every=0 --set run.seed=$SEED 2>&1 | tail -2
cp $run/metrics.jsonl $HERE/metrics-v2-$SEED.jsonl
for u in 2560 2816 2929; do
  echo "== validate v2-$SEED $u $(date -u +%T)"
  $K validation run $run/checkpoints/$u --finetune-seeds '' --json $HERE/val-v2-$SEED-$u.json 2>&1 | tail -1
done
echo "== done $(date -u +%T)"
