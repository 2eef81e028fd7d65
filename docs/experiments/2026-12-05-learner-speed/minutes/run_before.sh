#!/bin/bash
# The before side of the minutes to 15.3% (README.md, "The code issue 70 found, at 24M"): the general recipe on
# 11c143b's code (a worktree on PYTHONPATH whose checkpoint retention is raised from 3 to 100; nothing else changed),
# training seed $1, 1 device, then every checkpoint from 1,024 and the final one on the validation suite with
# today's `kinetix validation`. Runs in /tmp/minutes; metrics and scores land next to this script.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/minutes
OUT=/tmp/minutes
SEED=${1:?training seed}
K=.venv/bin/kinetix
if [ ! -d /tmp/wt-before ]; then
  git worktree add --detach /tmp/wt-before 11c143b
  sed -i 's/^KEEP = 3/KEEP = 100/' /tmp/wt-before/src/kinetix_cli/rl/checkpoints.py
fi
echo "== code $(git -C /tmp/wt-before rev-parse HEAD) + $(git -C /tmp/wt-before diff --stat | tail -1)"
mkdir -p $OUT
run=$OUT/before-$SEED
echo "== train $SEED $(date -u +%T)"
PYTHONPATH=/tmp/wt-before/src KINETIX_CPU_DEVICES=1 $K pretrain --config experiments/general.yaml --run-dir $run \
  --set run.eval_every=0 --set run.checkpoint_every=256 --set run.seed=$SEED 2>&1 | tail -2
cp $run/metrics.jsonl $HERE/metrics-before-$SEED.jsonl
for ckpt in $(ls $run/checkpoints | sort -n); do
  [ "$ckpt" -ge 1024 ] || continue
  echo "== validate before-$SEED $ckpt $(date -u +%T)"
  $K validation run $run/checkpoints/$ckpt --finetune-seeds '' --json $HERE/val-before-$SEED-$ckpt.json 2>&1 | tail -1
done
echo "== done $(date -u +%T)"
