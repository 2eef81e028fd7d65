#!/bin/bash
# Mixed precision on the faster VM of the seventh session, where a bfloat16 matmul at the update's shapes measured
# 1.00-1.29x the float32 one (restarts/breakdown-*.json): float32 and bfloat16 in one command, twice, default devices.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/bf16-fast-vm
for round in 1 2; do
  echo "== round $round $(date -u +%T)"
  .venv/bin/kinetix bench train --models rel-mlp --size s --envs 256 --width 64 --layers 3 --steps 32 --epochs 4 \
    --minibatches 4 --compute float32,bfloat16 --min-time 30 --json $HERE/round-$round.json 2>&1 | grep -E "rel-mlp" | grep -v "│"
done
