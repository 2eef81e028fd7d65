#!/bin/bash
# README.md here, third part: SFL's scoring beside rel-mlp's update in the breakdown, the shipped 4 x 4 and 1 x 16.
set -euo pipefail
cd "$(dirname "$0")/../../../.."
HERE=docs/experiments/2026-12-05-learner-speed/final
ARGS="bench train --breakdown --models rel-mlp --size s --envs 256 --width 64 --layers 3 --steps 32"
echo "== $(git rev-parse --short HEAD) $(date -u +%F\ %T) UTC"
.venv/bin/kinetix $ARGS --json $HERE/scoring-4x4.json 2>&1 | tail -30
echo "== one epoch $(date -u +%T)"
.venv/bin/kinetix $ARGS --epochs 1 --minibatches 16 --json $HERE/scoring-1x16.json 2>&1 | tail -30
echo "== done $(date -u +%T)"
