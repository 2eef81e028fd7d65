#!/bin/bash
# Issue 70's closing measurements (README.md here), each alone on the VM:
# 1. speed: 11c143b (as issue 70 found it: 1 device, 4 epochs x 4 minibatches), HEAD's shipped recipe (4 x 4, 2
#    devices by default) and HEAD at 1 epoch x 16 minibatches, in that order, twice (speed-SIDE-ROUND.json);
# 2. every model's breakdown at s and m on HEAD (breakdown-SIZE.json / .txt; one device, as the breakdown measures).
set -euo pipefail
cd "$(dirname "$0")/../../../.."
HERE=docs/experiments/2026-12-05-learner-speed/final
rm -rf /tmp/wt-final-before; git worktree prune; git worktree add -q --detach /tmp/wt-final-before 11c143b
echo "== HEAD $(git rev-parse --short HEAD), $(date -u +%F\ %T) UTC"
ARGS="bench train --models rel-mlp --size s --envs 256 --width 64 --layers 3 --steps 32 --min-time 20"
for round in 1 2; do
  for side in before head one-epoch; do
    PP=$PWD/src; SHAPE="--epochs 4 --minibatches 4"
    [ $side = before ] && PP=/tmp/wt-final-before/src
    [ $side = one-epoch ] && SHAPE="--epochs 1 --minibatches 16"
    echo "== round $round $side $(date -u +%T)"
    PYTHONPATH=$PP .venv/bin/kinetix $ARGS $SHAPE --json $HERE/speed-$side-$round.json 2>&1 | grep -E "rel-mlp" | tail -1
  done
done
.venv/bin/python - <<'PY'
import json
here = "docs/experiments/2026-12-05-learner-speed/final"
for r in (1, 2):
    sps = {s: json.load(open(f"{here}/speed-{s}-{r}.json"))["results"][0]["steps_per_s"] for s in ("before", "head", "one-epoch")}
    print(f"round {r}: " + ", ".join(f"{s} {v:,.0f} ({v / sps['before']:.2f}x)" for s, v in sps.items()))
PY
for size in s m; do
  echo "== breakdown $size $(date -u +%T)"
  .venv/bin/kinetix bench train --breakdown --models flat-mlp,pi-mlp,rel-mlp,transformer --size $size --envs 256 \
    --width 64 --layers 3 --steps 32 --json $HERE/breakdown-$size.json 2>&1 | tee $HERE/breakdown-$size.txt
done
git worktree remove --force /tmp/wt-final-before
echo "== done $(date -u +%T)"
