#!/usr/bin/env bash
# Does XLA's GPU autotuning dominate the PPO update's compile time? pi-mlp train bench with and without it.
set -uo pipefail
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 1
export PYTHONPATH=/tmp/site:$PWD/src PYTHONUNBUFFERED=1
run() { python3 -c "import sys; from kinetix_cli.cli.app import main; sys.argv[0] = 'kinetix'; main()" bench train --size m --models pi-mlp --envs 2048 --steps 64 --epochs 8 --minibatches 32 --width 128 --layers 5 --min-time 3 --json "$OUT/$1.json" 2>&1 | grep -v "━\|┃\|┏\|┡\|└" | tee -a "$OUT/log"; }
for f in "--xla_gpu_autotune_level=0" ""; do
  s=$(date +%s); echo "XLA_FLAGS='$f'" | tee -a "$OUT/log"
  XLA_FLAGS="$f" run "autotune${f:+-off}"
  echo "process seconds: $(($(date +%s) - s))" | tee -a "$OUT/log"
done
