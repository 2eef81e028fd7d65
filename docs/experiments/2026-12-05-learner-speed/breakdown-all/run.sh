#!/bin/bash
# Issue 70's breakdown table: every model (flat-mlp, pi-mlp, rel-mlp, transformer) at sizes s and m with the general
# recipe's width, layers and batch (64, 3, 256 envs x 32 steps), on one device as the breakdown measures; one run per
# size, each alone on the VM. Output: s.json, m.json and the printed tables next to this script; table.py prints the
# study's table from the JSON files.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/breakdown-all
for size in s m; do
  echo "== $size $(date -u +%T)"
  .venv/bin/kinetix bench train --breakdown --models flat-mlp,pi-mlp,rel-mlp,transformer --size $size --envs 256 \
    --width 64 --layers 3 --steps 32 --json $HERE/$size.json 2>&1 | tee $HERE/$size.txt
done
echo "== done $(date -u +%T)"
