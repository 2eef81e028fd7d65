#!/bin/bash
# One SFL refresh of the general recipe before (the commit given as $1, a worktree) and after (this checkout's
# src), alternating B A B A on 2 devices (kinetix's default here), then on 1, each alone; no compile cache.
# Output: ab.jsonl next to this script, one line per process with its side.
set -euo pipefail
cd /work/main
HERE=docs/experiments/2026-12-05-learner-speed/sfl-one-call
BEFORE=${1:?commit before}
[ -d /tmp/wt-sfl-before ] || git worktree add --detach /tmp/wt-sfl-before "$BEFORE"
: > $HERE/ab.jsonl
for devices in 2 1; do
  for round in 1 2; do
    for side in before after; do
      src=$([ $side = before ] && echo /tmp/wt-sfl-before/src || echo src)
      line=$(KINETIX_CPU_DEVICES=$devices PYTHONPATH=$src .venv/bin/python $HERE/time_refresh.py 5)
      echo "{\"side\": \"$side\", \"round\": $round, ${line:1}" | tee -a $HERE/ab.jsonl
    done
  done
done
