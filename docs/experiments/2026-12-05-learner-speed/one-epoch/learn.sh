#!/bin/bash
# The learning rule of README.md here, for the recipe the speed rule chose: $1 = its epochs, $2 = its minibatches.
# First drift.sh's check (11c143b's plain update tonight), then seeds 0-2 on HEAD (a worktree of the commit given
# as $3), each with the same seed's 11c143b minutes as `run.minutes`, checkpoints at 768 and at the budget's end;
# then every checkpoint on the validation suite. Runs in /tmp/one-epoch; records are copied next to this script.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/one-epoch
OUT=/tmp/one-epoch
EPOCHS=${1:?epochs}; MINIBATCHES=${2:?minibatches}; COMMIT=${3:?commit}
K=.venv/bin/kinetix
[ -d /tmp/wt-epoch ] || git worktree add --detach /tmp/wt-epoch "$COMMIT"
[ -d /tmp/wt-before ] || git worktree add --detach /tmp/wt-before 11c143b
mkdir -p $OUT
COMMON="--config experiments/general.yaml --set run.eval_every=0"
echo "== drift: 11c143b, 64 updates $(date -u +%T)"
PYTHONPATH=/tmp/wt-before/src $K pretrain $COMMON --set run.checkpoint_every=0 --run-dir $OUT/drift \
  --set ppo.total_timesteps=524288 2>&1 | tail -1
cp $OUT/drift/metrics.jsonl $HERE/metrics-drift.jsonl
declare -A BUDGET=([0]=10.31 [1]=10.21 [2]=10.40)  # ../learning/README.md, "before again"
for seed in 0 1 2; do
  echo "== $EPOCHS x $MINIBATCHES, seed $seed $(date -u +%T), ${BUDGET[$seed]} min"
  PYTHONPATH=/tmp/wt-epoch/src $K pretrain $COMMON --set run.checkpoint_every=768 --run-dir $OUT/epoch-$seed \
    --set run.seed=$seed --set run.minutes=${BUDGET[$seed]} --set ppo.update_epochs=$EPOCHS \
    --set ppo.num_minibatches=$MINIBATCHES 2>&1 | tail -1
  cp $OUT/epoch-$seed/metrics.jsonl $HERE/metrics-epoch-$seed.jsonl
done
for seed in 0 1 2; do
  for ckpt in $OUT/epoch-$seed/checkpoints/*; do
    name=epoch-$seed-$(basename $ckpt)
    echo "== validate $name $(date -u +%T)"
    $K validation run $ckpt --finetune-seeds '' --json $HERE/val-$name.json 2>&1 | tail -1
  done
done
echo "== done $(date -u +%T)"
