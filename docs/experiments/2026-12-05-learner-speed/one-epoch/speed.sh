#!/bin/bash
# The speed rule of README.md here: 11c143b (1 device, as it ran), 41af707 (before the arena sides left the
# encoders), HEAD (the shipped recipe's 4 x 4), and candidates A (1 epoch x 16 minibatches), B (1 x 8), C (1 x 4) on
# HEAD, each alone, in that order, twice. Results: SIDE-ROUND.json.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/one-epoch
[ -d /tmp/wt-before ] || git worktree add --detach /tmp/wt-before 11c143b
[ -d /tmp/wt-sides ] || git worktree add --detach /tmp/wt-sides 41af707
echo "== HEAD $(git rev-parse --short HEAD)"
ARGS="bench train --models rel-mlp --size s --envs 256 --width 64 --layers 3 --steps 32 --min-time 20"
for round in 1 2; do
  for side in before sides head A B C; do
    PP=/work/main/src
    case $side in
      before) PP=/tmp/wt-before/src; SHAPE="--epochs 4 --minibatches 4" ;;
      sides) PP=/tmp/wt-sides/src; SHAPE="--epochs 4 --minibatches 4" ;;
      head) SHAPE="--epochs 4 --minibatches 4" ;;
      A) SHAPE="--epochs 1 --minibatches 16" ;;
      B) SHAPE="--epochs 1 --minibatches 8" ;;
      C) SHAPE="--epochs 1 --minibatches 4" ;;
    esac
    echo "== round $round $side $(date -u +%T)"
    PYTHONPATH=$PP .venv/bin/kinetix $ARGS $SHAPE --json $HERE/$side-$round.json 2>&1 | grep -E "rel-mlp" | tail -1
  done
done
.venv/bin/python - <<'PY'
import json
here = "docs/experiments/2026-12-05-learner-speed/one-epoch"
for r in (1, 2):
    sps = {s: json.load(open(f"{here}/{s}-{r}.json"))["results"][0]["steps_per_s"] for s in ("before", "sides", "head", "A", "B", "C")}
    print(f"round {r}: " + ", ".join(f"{s} {v:,.0f} ({v / sps['before']:.2f}x)" for s, v in sps.items()))
PY
echo "== breakdown, HEAD, 1 device $(date -u +%T)"  # the FLOPs without the arena sides (../breakdown-all/s.json: before)
.venv/bin/kinetix $ARGS --epochs 4 --minibatches 4 --breakdown --json $HERE/breakdown-head.json 2>&1 | tail -12
