#!/usr/bin/env bash
# The runs behind BENCHMARKS.md's fine-tuning figures: general-s fine-tuned on one level with the default settings
# and with the entropy recipe, against training from scratch, 3 seeds each, 102,400 env steps, each run evaluating
# itself every 10 updates; then general-s and every run evaluated on all of levels/s (what fine-tuning on one
# level does to the others). Runs already finished are kept. The figures are made from OUT_DIR by the commands
# shown under them in BENCHMARKS.md.
#
#   benchmarks/finetune_figures.sh OUT_DIR [LEVEL]    (LEVEL: levels/s/pad-to-pad.json)
set -euo pipefail
out=${1:?usage: $0 OUT_DIR [LEVEL]}
level=${2:-levels/s/pad-to-pad.json}
kinetix=${KINETIX:-.venv/bin/kinetix}
common=(--config experiments/cpu-small.yaml --set ppo.total_timesteps=102400 --set run.eval_every=10)
arm() { # NAME SEED FINETUNE-ARGS...
  local dir=$out/$1-$2
  shift 2
  [ -f "$dir/eval-levels-s.json" ] && return # done in an earlier call
  rm -rf "$dir"
  "$kinetix" finetune "$level" --run-dir "$dir" "${common[@]}" "$@"
  "$kinetix" eval "$dir" --levels levels/s --attempts 20 --seed 1000 --json "$dir/eval-levels-s.json"
}
for seed in 0 1 2; do
  arm finetuned "$seed" --from general-s --set run.seed="$seed"
  arm recipe "$seed" --from general-s --set run.seed="$seed" --set ppo.ent_coef=0.05 --set ppo.ent_coef_end=0.01
  arm scratch "$seed" --from none --set run.seed="$seed"
done
[ -f "$out/general-s-levels-s.json" ] ||
  "$kinetix" eval general-s --levels levels/s --attempts 20 --seed 1000 --json "$out/general-s-levels-s.json"
