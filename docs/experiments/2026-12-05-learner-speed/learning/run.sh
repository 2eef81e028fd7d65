#!/bin/bash
# Part 4's learning table (see README.md here): before (11c143b on PYTHONPATH, 768 updates) and after (HEAD, the
# same seed's training minutes as a budget), seeds 0-2 alternating, then every checkpoint on the validation suite.
# (The runs of 2026-12-05 ran "after" from the working tree, which then held 8933519's source: see README.md, Results.)
# Runs in /tmp/learn; the metrics and validation records are copied next to this script.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/learning
OUT=/tmp/learn
K=.venv/bin/kinetix
[ -d /tmp/wt-before ] || git worktree add --detach /tmp/wt-before 11c143b
mkdir -p $OUT
COMMON="--config experiments/general.yaml --set run.eval_every=0 --set run.checkpoint_every=768"
for seed in 0 1 2; do
  echo "== before $seed $(date -u +%T)"
  PYTHONPATH=/tmp/wt-before/src $K pretrain $COMMON --run-dir $OUT/before-$seed --set run.seed=$seed \
    --set ppo.total_timesteps=6291456 2>&1 | tail -2
  minutes=$(.venv/bin/python -c "
import json, sys
rows = [json.loads(line) for line in open('$OUT/before-$seed/metrics.jsonl') if '\"sps\"' in line]
print(round(sum(8192 / r['sps'] for r in rows) / 60, 3))")
  echo "== after $seed $(date -u +%T) budget $minutes min"
  $K pretrain $COMMON --run-dir $OUT/after-$seed --set run.seed=$seed --set run.minutes=$minutes 2>&1 | tail -2
done
$K validation build >/dev/null  # the held-out levels, once
for run in $OUT/before-* $OUT/after-*; do
  for ckpt in $run/checkpoints/*; do
    name=$(basename $run)-$(basename $ckpt)
    echo "== validate $name $(date -u +%T)"
    $K validation run $ckpt --finetune-seeds '' --json $OUT/val-$name.json 2>&1 | tail -1
  done
done
for run in $OUT/before-* $OUT/after-*; do cp $run/metrics.jsonl $HERE/metrics-$(basename $run).jsonl; done
cp $OUT/val-*.json $HERE/
echo "== done $(date -u +%T)"
