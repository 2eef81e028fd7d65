#!/bin/bash
cd /work/main
for i in 1 2 3; do
  rm -rf /tmp/reprof-$i
  echo "== flag try $i $(date -u +%T)"
  XLA_FLAGS="--xla_cpu_enable_concurrency_optimized_scheduler=false" .venv/bin/kinetix pretrain --config experiments/general.yaml --set ppo.total_timesteps=1048576 --set run.eval_every=0 --set run.seed=2 --set run.minutes=30 --set run.checkpoint_every=768 --run-dir /tmp/reprof-$i > /tmp/reprof-$i.log 2>&1
  echo "rc=$? $(date -u +%T) $(grep -c sps /tmp/reprof-$i/metrics.jsonl 2>/dev/null)"
done
