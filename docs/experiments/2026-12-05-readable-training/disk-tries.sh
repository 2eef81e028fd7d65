#!/bin/bash
# The full-disk race, five tries (as root): a pi-mlp run (experiments/cpu-small.yaml) checkpointing every 4 updates on
# a fresh 600 KB tmpfs at $SMALL; each try's stderr goes to disk-$1-N.stderr beside this script. Before the fix,
# orbax's writer threads and abandoned asyncio tasks printed tracebacks around the one error line.
#   bash docs/experiments/2026-12-05-readable-training/disk-tries.sh after
here=$(cd "$(dirname "$0")" && pwd)
SMALL=${SMALL:-/tmp/kinetix-small-disk}
cd "$here/../../.." && mkdir -p "$SMALL"
for i in 1 2 3 4 5; do
  mountpoint -q "$SMALL" && umount "$SMALL"
  mount -t tmpfs -o size=600k tmpfs "$SMALL"
  timeout 600 .venv/bin/kinetix pretrain --config experiments/cpu-small.yaml --run-dir "$SMALL/run" \
    --set run.checkpoint_every=4 --set ppo.total_timesteps=100000 --set run.eval_every=0 > /dev/null 2> "$here/disk-$1-$i.stderr"
  echo "$1 try $i: exit $?, stderr lines $(wc -l < "$here/disk-$1-$i.stderr")"
done
umount "$SMALL"
