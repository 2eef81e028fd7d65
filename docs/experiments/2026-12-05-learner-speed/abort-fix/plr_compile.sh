#!/bin/bash
# PLR's compile, one program holding every round (a702482) against one program per round (the fix, $1): the
# cpu-plr recipe's first 16 updates (8 of new levels fill the buffer, then rounds mix), no compile cache, each side alone, P F P F. Prints the wall time and each
# update's seconds with its round (the first update of each round compiles that round's program on F).
set -euo pipefail
cd /work/main
FIX=${1:?commit of the fix}
[ -d /tmp/wt-p ] || git worktree add --detach /tmp/wt-p a702482
[ -d /tmp/wt-f ] || git worktree add --detach /tmp/wt-f "$FIX"
for round in 1 2; do
  for side in p f; do
    rm -rf /tmp/plr-$side-$round
    start=$(date +%s.%N)
    KINETIX_COMPILE_CACHE=off PYTHONPATH=/tmp/wt-$side/src .venv/bin/kinetix pretrain --config experiments/cpu-plr.yaml \
      --set ppo.total_timesteps=131072 --set run.eval_every=0 --run-dir /tmp/plr-$side-$round > /dev/null 2>&1
    wall=$(echo "$(date +%s.%N) - $start" | bc)
    .venv/bin/python -c "
import json
rows = [json.loads(l) for l in open('/tmp/plr-$side-$round/metrics.jsonl')]
print('$side round $round: wall $wall s;', ', '.join(f\"{'R' if r['replay'] else 'n'} {8192 / r['sps']:.1f}\" for r in rows))"
  done
done
