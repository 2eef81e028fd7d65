#!/usr/bin/env bash
# Which model learns most per wall-clock second on this machine: each entry trains with DR on fresh levels for the
# number of env steps that its measured training throughput (`kinetix bench train`, 256 envs x 32 steps, 3 layers)
# fits into the time pi-mlp width 64 takes for REFERENCE_STEPS; every final policy is evaluated zero-shot with
# ATTEMPTS sampled episodes per level on the hand-made suites; curricula_summary.py prints the table.
#
#   benchmarks/models.sh OUT_DIR
#   ENTRIES="flat-mlp:64:5800000:0,1 ..." (model:width:steps:seeds, defaults below), CONFIG=experiments/cpu-small.yaml
#   ATTEMPTS=20 ENVS=256 SUITES="levels/s .cache/reference-levels/s"
#
# The default steps come from `kinetix bench train --models flat-mlp,pi-mlp,transformer --envs 256 --steps 32
# --layers 3 --width 64|128` (2026-11-25: 29.8K, 10.2K, 1.1K env steps/s at width 64; 19.3K, 4.6K, 0.39K at 128,
# measured back to back) scaled to pi-mlp 64's 2M steps; pi-mlp 64 itself is the `dr` row of benchmarks/curricula.sh.
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: $0 OUT_DIR" >&2
  exit 2
fi
out=$1
kinetix=${KINETIX:-.venv/bin/kinetix}
python=${PYTHON:-.venv/bin/python}
entries=${ENTRIES:-flat-mlp:64:5800000:0,1 flat-mlp:128:3800000:0,1 pi-mlp:128:900000:0,1 transformer:64:210000:0,1}
suites=${SUITES:-levels/s .cache/reference-levels/s}
mkdir -p "$out"
for entry in $entries; do
  IFS=: read -r model width steps seeds <<<"$entry"
  for seed in ${seeds//,/ }; do
    dir=$out/$model-$width-$seed
    [ -f "$dir/eval.json" ] && continue # done in an earlier call
    rm -rf "$dir"                         # an unfinished run starts over (its wall-clock time is part of the result)
    obs=symbolic-entity
    [ "$model" = flat-mlp ] && obs=symbolic-flat
    start=$(date +%s)
    "$kinetix" pretrain --run-dir "$dir" --config "${CONFIG:-experiments/cpu-small.yaml}" --set env.size=s \
      --set levels.source=fresh --set model.name="$model" --set model.width="$width" --set env.observation=$obs \
      --set "ppo.num_envs=${ENVS:-256}" --set ppo.num_steps=32 --set "ppo.total_timesteps=$steps" \
      --set "run.seed=$seed" --set run.eval_every=0
    echo "$(($(date +%s) - start))" >"$dir/wall_seconds"
    # shellcheck disable=SC2086 # suites are space-separated folders
    "$(dirname "$0")/zero_shot.sh" "$dir" $suites
  done
done
"$python" "$(dirname "$0")/curricula_summary.py" "$out"
