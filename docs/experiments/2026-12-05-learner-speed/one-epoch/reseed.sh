#!/bin/bash
# README.md's "Another seed from a fresh clone": the 1 x 16 recipe for training seed $2 (default 3) in the fresh clone
# $1 (default /tmp/fresh, with its .venv), run.minutes 10.31, then its checkpoints on the validation suite. Records
# land next to this script.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
CLONE=${1:-/tmp/fresh}; SEED=${2:-3}
cd $CLONE
echo "== clone $(git rev-parse --short HEAD), seed $SEED $(date -u +%T)"
.venv/bin/kinetix pretrain --config experiments/general.yaml --set run.eval_every=0 --set run.checkpoint_every=768 \
  --run-dir /tmp/reseed-$SEED --set run.seed=$SEED --set run.minutes=10.31 --set ppo.update_epochs=1 \
  --set ppo.num_minibatches=16 2>&1 | tail -1
cp /tmp/reseed-$SEED/metrics.jsonl $HERE/metrics-epoch-$SEED.jsonl
for ckpt in /tmp/reseed-$SEED/checkpoints/*; do
  echo "== validate $(basename $ckpt) $(date -u +%T)"
  .venv/bin/kinetix validation run $ckpt --finetune-seeds '' --json $HERE/val-epoch-$SEED-$(basename $ckpt).json \
    2>&1 | tail -1
done
echo "== done $(date -u +%T)"
