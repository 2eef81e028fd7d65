#!/bin/bash
# Restarting only the ended episodes (`env.environment.step_batch`), measured in one run, each side alone, in the
# order A B C D A B C D: A = 11c143b (the code issue 70 was filed against, 1 CPU device as it ran), B = 64b6028
# (before this change, 2 devices by default), C = 8933519 (this change, 2 devices by default; the working tree
# when it ran, a worktree now that the change is reverted), D = 8933519 on 1 device (KINETIX_CPU_DEVICES=1). The general recipe's update shape
# (rel-mlp 64 x 3, size s, 256 envs x 32 steps, 4 epochs x 4 minibatches). Worktrees of A and B on PYTHONPATH.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/restarts
[ -d /tmp/wt-before ] || git worktree add --detach /tmp/wt-before 11c143b
[ -d /tmp/wt-prev ] || git worktree add --detach /tmp/wt-prev 64b6028
[ -d /tmp/wt-restart ] || git worktree add --detach /tmp/wt-restart 8933519
ARGS="bench train --models rel-mlp --size s --envs 256 --width 64 --layers 3 --steps 32 --epochs 4 --minibatches 4 --min-time 30"
for round in 1 2; do
  for side in A B C D; do
    DEV=
    case $side in A) PP=/tmp/wt-before/src ;; B) PP=/tmp/wt-prev/src ;; C) PP=/tmp/wt-restart/src ;; D) PP=/tmp/wt-restart/src DEV=1 ;; esac
    echo "== round $round $side $(date -u +%T)"
    KINETIX_CPU_DEVICES=$DEV PYTHONPATH=$PP .venv/bin/kinetix $ARGS --json $HERE/$side-$round.json 2>&1 | grep -E "rel-mlp" | tail -2
  done
done
echo "== breakdown, C, 1 device $(date -u +%T)"
PYTHONPATH=/tmp/wt-restart/src .venv/bin/kinetix $ARGS --breakdown --json $HERE/breakdown-C.json 2>&1 | tail -25
echo "== breakdown, B, 1 device $(date -u +%T)"
PYTHONPATH=/tmp/wt-prev/src .venv/bin/kinetix $ARGS --breakdown --json $HERE/breakdown-B.json 2>&1 | tail -25
