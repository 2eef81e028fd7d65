#!/usr/bin/env bash
# Issue 47: the engine and training benchmarks before (53de560, the tree before this session) and after (issue47
# branch), one run, interleaved, on this machine; compile cache off so compile times compare.
set -euo pipefail
OUT=/tmp/bench47
PY=/work/main/.venv/bin/python
K="-c from kinetix_cli.cli.app import main; main()"
export JAX_COMPILATION_CACHE_DIR=
run() {  # name tree args...
  local name=$1 tree=$2; shift 2
  (cd "$tree" && PYTHONPATH="$tree/src" "$PY" -c "from kinetix_cli.cli.app import main; main()" "$@") > "$OUT/$name.log" 2>&1
}
lscpu | grep "Model name" > $OUT/machine.txt; date -u >> $OUT/machine.txt
for side in before after; do tree=/tmp/before47; [ $side = after ] && tree=/work/wt47
  run engine-s-$side $tree bench engine --size s --envs 64,1024 --json $OUT/engine-s-$side.json; done
for side in before after; do tree=/tmp/before47; [ $side = after ] && tree=/work/wt47
  run engine-m-$side $tree bench engine --size m --envs 64,1024 --json $OUT/engine-m-$side.json; done
for side in before after; do tree=/tmp/before47; [ $side = after ] && tree=/work/wt47
  run train-$side $tree bench train --size s --models pi-mlp,rel-mlp --envs 64 --width 64 --json $OUT/train-$side.json; done
for side in before after; do tree=/tmp/before47; [ $side = after ] && tree=/work/wt47
  rm -rf $OUT/sfl-$side
  start=$(date +%s)
  run sfl-$side $tree pretrain --config experiments/cpu-small.yaml --run-dir $OUT/sfl-$side --set curriculum.name=sfl \
    --set curriculum.refresh_every=8 --set ppo.total_timesteps=81920 --set run.eval_every=0 --set run.checkpoint_every=0
  echo "$side wall $(( $(date +%s) - start )) s" >> $OUT/sfl-wall.txt
done
echo done > $OUT/finished
