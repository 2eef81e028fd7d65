#!/bin/bash
# The abort fix's cost, measured in one run, each side alone, alternating: P = a702482 (before the fix), F = the fix
# (a worktree of the commit given as $1). (1) `kinetix bench train` at the general recipe's update shape (rel-mlp
# 64 x 3, size s, 256 envs x 32 steps, 4 x 4 minibatches; DR on random levels: only `final_values` changed), 2
# devices; (2) the general recipe itself (fresh levels, SFL), a minute of training per run, 2 devices: P and F with
# XLA's concurrency-optimised scheduler off (P aborts with it on), F also as it ships (flag on).
# Rate of (2): the median seconds of the plain updates (8192 / sps, updates 2..N without SFL's refresh).
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/abort-fix
FIX=${1:?commit of the fix}
[ -d /tmp/wt-p ] || git worktree add --detach /tmp/wt-p a702482
[ -d /tmp/wt-f ] || git worktree add --detach /tmp/wt-f "$FIX"
FLAG=--xla_cpu_enable_concurrency_optimized_scheduler=false
BENCH="bench train --models rel-mlp --size s --envs 256 --width 64 --layers 3 --steps 32 --epochs 4 --minibatches 4 --min-time 30"
RECIPE="pretrain --config experiments/general.yaml --set ppo.total_timesteps=1048576 --set run.eval_every=0 --set run.seed=2 --set run.minutes=1 --set run.checkpoint_every=768"
median() {
  .venv/bin/python -c "
import json, statistics, sys
rows = [json.loads(l) for l in open('$1') if '\"sps\"' in l]
plain = [8192 / r['sps'] for r in rows[1:] if r['update'] % 64 != 1]
print(f'{len(rows)} updates, plain update median {statistics.median(plain):.3f} s ({8192 / statistics.median(plain):,.0f} env steps/s)')"
}
for round in 1 2; do
  for side in P F; do
    PP=/tmp/wt-$(echo $side | tr PF pf)/src
    echo "== bench $side round $round $(date -u +%T)"
    PYTHONPATH=$PP .venv/bin/kinetix $BENCH --json $HERE/bench-$side-$round.json 2>&1 | grep -E "rel-mlp" | tail -2
  done
  for case in P-flag F-flag F; do
    side=${case%%-*}; PP=/tmp/wt-$(echo $side | tr PF pf)/src; X=; [ "$case" != F ] && X=$FLAG
    rm -rf /tmp/ab-$case-$round
    echo "== recipe $case round $round $(date -u +%T)"
    XLA_FLAGS=$X PYTHONPATH=$PP .venv/bin/kinetix $RECIPE --run-dir /tmp/ab-$case-$round > /tmp/ab-$case-$round.log 2>&1 || echo "rc=$?"
    cp /tmp/ab-$case-$round/metrics.jsonl $HERE/recipe-$case-$round.jsonl
    median /tmp/ab-$case-$round/metrics.jsonl
  done
done
echo "== done $(date -u +%T)"
