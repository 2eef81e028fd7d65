#!/bin/bash
# What XLA's concurrency-optimised scheduler switched off costs the benchmark's update (2 devices, default), in one
# run, alternating: default, flag, default, flag.
set -euo pipefail
cd /work/main
ARGS="bench train --models rel-mlp --size s --envs 256 --width 64 --layers 3 --steps 32 --epochs 4 --minibatches 4 --min-time 30"
for round in 1 2; do
  for side in default flag; do
    FLAGS=""
    [ $side = flag ] && FLAGS="--xla_cpu_enable_concurrency_optimized_scheduler=false"
    echo "== $side $round $(date -u +%T)"
    XLA_FLAGS="$FLAGS" .venv/bin/kinetix $ARGS 2>&1 | grep -E "rel-mlp" | grep -v "│"
  done
done
