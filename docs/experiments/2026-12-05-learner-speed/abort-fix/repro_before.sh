#!/bin/bash
# The abort's command (recipe-gap/repro.sh), repeated on the code before the fix (a702482, a worktree on
# PYTHONPATH): a minute of training each (the aborts came in the first update), default CPU split (2 devices), no
# XLA flags. Prints each try's exit code and updates written.
cd "$(dirname "$0")/../../../.."
tries=${1:-4}
[ -d /tmp/wt-p ] || git worktree add --detach /tmp/wt-p a702482
export PYTHONPATH=/tmp/wt-p/src
for i in $(seq 1 "$tries"); do
  rm -rf /tmp/repro-before-$i
  echo "== try $i $(date -u +%T)"
  .venv/bin/kinetix pretrain --config experiments/general.yaml --set ppo.total_timesteps=1048576 --set run.eval_every=0 \
    --set run.seed=2 --set run.minutes=1 --set run.checkpoint_every=768 --run-dir /tmp/repro-before-$i > /tmp/repro-before-$i.log 2>&1
  echo "rc=$? $(date -u +%T) updates=$(grep -c sps /tmp/repro-before-$i/metrics.jsonl 2>/dev/null) aborts=$(grep -c 'Termination timeout' /tmp/repro-before-$i.log)"
done
