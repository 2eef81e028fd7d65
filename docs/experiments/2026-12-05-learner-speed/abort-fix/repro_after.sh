#!/bin/bash
# The abort's command (recipe-gap/repro.sh), repeated on the fixed code (the working tree): a minute of training
# each (the aborts came in the first update), default CPU split (2 devices), no XLA flags. Prints each try's exit
# code and updates written.
cd "$(dirname "$0")/../../../.."
tries=${1:-6}
for i in $(seq 1 "$tries"); do
  rm -rf /tmp/repro-after-$i
  echo "== try $i $(date -u +%T)"
  .venv/bin/kinetix pretrain --config experiments/general.yaml --set ppo.total_timesteps=1048576 --set run.eval_every=0 \
    --set run.seed=2 --set run.minutes=1 --set run.checkpoint_every=768 --run-dir /tmp/repro-after-$i > /tmp/repro-after-$i.log 2>&1
  echo "rc=$? $(date -u +%T) updates=$(grep -c sps /tmp/repro-after-$i/metrics.jsonl 2>/dev/null) aborts=$(grep -c 'Termination timeout' /tmp/repro-after-$i.log)"
done
