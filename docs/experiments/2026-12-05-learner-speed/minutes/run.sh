#!/bin/bash
# The minutes to 15.3% (README.md here, written before the runs): the general-s recipe's whole 24M env steps for
# training seeds 0-2 with the code of the commit given as $1 (a worktree on PYTHONPATH), then the checkpoints on the
# validation suite in the README's order. Runs in /tmp/minutes; metrics and validation records land next to this
# script; summary.py prints the table.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/minutes
OUT=/tmp/minutes
COMMIT=${1:?commit of today\'s code}
K=.venv/bin/kinetix
[ -d /tmp/wt-minutes ] || git worktree add --detach /tmp/wt-minutes "$COMMIT"
export PYTHONPATH=/tmp/wt-minutes/src
echo "== code $(git -C /tmp/wt-minutes rev-parse HEAD)"
mkdir -p $OUT
for seed in 0 1 2; do
  echo "== train $seed $(date -u +%T)"
  $K pretrain --config experiments/general.yaml --set run.eval_every=0 --set run.checkpoint_every=256 \
    --run-dir $OUT/today-$seed --set run.seed=$seed 2>&1 | tail -2
  cp $OUT/today-$seed/metrics.jsonl $HERE/metrics-today-$seed.jsonl
done
score() {  # score RUN UPDATE: validate the checkpoint once, print its zero-shot score as a fraction
  local json=$OUT/val-$(basename $1)-$2.json
  if [ ! -f $json ]; then
    echo "== validate $(basename $1) $2 $(date -u +%T)" >&2
    $K validation run $1/checkpoints/$2 --finetune-seeds '' --json $json 2>&1 | tail -1 >&2
    cp $json $HERE/
  fi
  .venv/bin/python -c "import json; print(json.load(open('$json'))['score']['zero_shot'])"
}
above() { .venv/bin/python -c "import sys; sys.exit(0 if float('$1') >= 0.153 else 1)"; }
for seed in 0 1 2; do
  run=$OUT/today-$seed
  last=$(ls $run/checkpoints | sort -n | tail -1)
  score $run $last > /dev/null
  if above "$(score $run 1024)"; then
    for u in 768 512 256; do above "$(score $run $u)" || break; done
  else
    for u in $(seq 1280 256 $last); do above "$(score $run $u)" && break; done
  fi
done
echo "== done $(date -u +%T)"
