#!/bin/bash
# The learning table's missing column (README.md here, "Today's code", written before the runs): for seeds 0-2,
# alternating, the before run again (11c143b, 768 updates: its training minutes on today's VM; its scores are those
# of run.sh's identical run), then today's code (the commit given as $1, a worktree on PYTHONPATH) given those
# minutes as `run.minutes`, checkpoints at 768 and at the budget's end; then today's checkpoints on the validation
# suite as the rule says.
# Runs in /tmp/learn-today; metrics and validation records are copied next to this script.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/learning
OUT=/tmp/learn-today
COMMIT=${1:?commit of today\'s code}
K=.venv/bin/kinetix
[ -d /tmp/wt-today ] || git worktree add --detach /tmp/wt-today "$COMMIT"
[ -d /tmp/wt-before ] || git worktree add --detach /tmp/wt-before 11c143b
export PYTHONPATH=/tmp/wt-today/src
mkdir -p $OUT
COMMON="--config experiments/general.yaml --set run.eval_every=0 --set run.checkpoint_every=768"
for seed in 0 1 2; do
  echo "== before again $seed $(date -u +%T)"
  PYTHONPATH=/tmp/wt-before/src $K pretrain $COMMON --run-dir $OUT/before-$seed --set run.seed=$seed \
    --set ppo.total_timesteps=6291456 2>&1 | tail -2
  minutes=$(.venv/bin/python -c "
import json
rows = [json.loads(line) for line in open('$OUT/before-$seed/metrics.jsonl') if '\"sps\"' in line]
print(round(sum(8192 / r['sps'] for r in rows) / 60, 3))")
  echo "== today $seed $(date -u +%T) budget $minutes min"
  $K pretrain $COMMON --run-dir $OUT/today-$seed --set run.seed=$seed --set run.minutes=$minutes 2>&1 | tail -2
done
for run in $OUT/today-*; do
  for ckpt in $run/checkpoints/*; do
    name=$(basename $run)-$(basename $ckpt)
    echo "== validate $name $(date -u +%T)"
    $K validation run $ckpt --finetune-seeds '' --json $OUT/val-$name.json 2>&1 | tail -1
  done
done
for run in $OUT/today-*; do cp $run/metrics.jsonl $HERE/metrics-$(basename $run).jsonl; done
for seed in 0 1 2; do cp $OUT/before-$seed/metrics.jsonl $HERE/metrics-before-again-$seed.jsonl; done
cp $OUT/val-today-*.json $HERE/
echo "== done $(date -u +%T)"
