#!/bin/bash
# ABAB: before (11c143b, PYTHONPATH to a worktree of it in /tmp/wt-before) and after (the working tree), the general
# recipe's update shape. onepass-*.json: after = one pass per step (b9a302c's tree), 05:34-05:38; final-*.json: after =
# that plus the attention mask only for the transformer, 06:25-06:28 (in abab/).
cd /work/main
ARGS="bench train --models rel-mlp --size s --envs 256 --width 64 --layers 3 --steps 32 --epochs 4 --minibatches 4 --min-time 20"
for round in 1 2; do
  for side in before after; do
    if [ $side = before ]; then PP=/tmp/wt-before/src; else PP=/work/main/src; fi
    echo "== round $round $side $(date +%T)"
    PYTHONPATH=$PP .venv/bin/kinetix $ARGS --json /tmp/ab/final-$side-$round.json 2>&1 | grep -E "rel-mlp|env steps" | tail -3
  done
done
