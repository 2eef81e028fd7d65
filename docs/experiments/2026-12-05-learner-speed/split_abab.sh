#!/bin/bash
# ABAB: before (11c143b, the code when issue 70 was filed: PYTHONPATH to a worktree of it in /tmp/wt-before) and
# after (the working tree: the waste out and the CPU split into one device per core by default), the general
# recipe's update shape, each as `kinetix` runs it by default. Results in split-abab/.
cd /work/main
mkdir -p /tmp/ab
ARGS="bench train --models rel-mlp --size s --envs 256 --width 64 --layers 3 --steps 32 --epochs 4 --minibatches 4 --min-time 20"
for round in 1 2; do
  for side in before after; do
    if [ $side = before ]; then PP=/tmp/wt-before/src; else PP=/work/main/src; fi
    echo "== round $round $side $(date +%T)"
    PYTHONPATH=$PP .venv/bin/kinetix $ARGS --json /tmp/ab/split-$side-$round.json 2>&1 | grep -E "rel-mlp|env steps" | tail -3
  done
done
