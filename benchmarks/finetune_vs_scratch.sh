#!/usr/bin/env bash
# Fine-tuning a pre-trained agent vs training from scratch on single levels: the same config, steps and seeds,
# only the initial parameters differ (`kinetix finetune --from RUN` vs `--from none`). Each run evaluates itself
# on its level every EVAL_EVERY updates (metrics.jsonl: eval_solve_rate) and is then scored with ATTEMPTS
# sampled episodes; summary.py prints the table.
#
#   benchmarks/finetune_vs_scratch.sh PRETRAINED_RUN STEPS OUT_DIR LEVEL...
#   SEEDS="0 1 2" CONFIG=experiments/cpu-small.yaml ATTEMPTS=50 EVAL_EVERY=10 (defaults)
#   SETS="model.name=rel-mlp ..." adds --set values to both arms (e.g. the pre-trained agent's model, so that the
#   scratch arm trains the same network: --from RUN inherits it, --from none takes the config's)
set -euo pipefail
if [ $# -lt 4 ]; then
  echo "usage: $0 PRETRAINED_RUN STEPS OUT_DIR LEVEL..." >&2
  exit 2
fi
run=$1 steps=$2 out=$3
shift 3
kinetix=${KINETIX:-.venv/bin/kinetix}
config=${CONFIG:-experiments/cpu-small.yaml}
sets=()
for s in ${SETS:-}; do sets+=(--set "$s"); done
for level in "$@"; do
  name=$(basename "$level" .json)
  for seed in ${SEEDS:-0 1 2}; do
    for from in "$run" none; do
      arm=finetuned
      [ "$from" = none ] && arm=scratch
      dir=$out/$name/$arm-$seed
      [ -f "$dir/eval.json" ] && continue # done in an earlier call
      rm -rf "$dir"
      "$kinetix" finetune "$level" --from "$from" --run-dir "$dir" --config "$config" \
        --set "ppo.total_timesteps=$steps" --set "run.seed=$seed" --set "run.eval_every=${EVAL_EVERY:-10}" "${sets[@]}"
      "$kinetix" eval "$dir" --levels "$level" --attempts "${ATTEMPTS:-50}" --seed 1000 --json "$dir/eval.json"
    done
  done
done
python3 "$(dirname "$0")/finetune_summary.py" "$out"
