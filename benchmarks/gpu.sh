#!/usr/bin/env bash
# The GPU benchmark, one script of about 8 minutes on one GPU: the engine against Jax2D at size m (1,024 to 16,384
# scenes: the paper's engine figure is at 16K), PPO training env steps/s with pi-mlp and the entity transformer at
# 2,048 envs (size m, the reference's 64 steps x 8 epochs x 32 minibatches) and the transformer at the paper's 32,768
# envs, and a few minutes of SFL with the transformer (experiments/pretrain-s.yaml, the reference recipe, then
# evaluated zero-shot with 50 attempts per level).
# gpu_summary.py prints the tables for BENCHMARKS.md.
#
#   benchmarks/gpu.sh OUT_DIR
#   TINY=1       the same steps at CPU sizes (seconds, not minutes): the smoke test of `make test-all`
#   MODELS       the training table's models (default pi-mlp,transformer; add rel-mlp, the v2 agents' model: ~45 s)
#   SFL_SECONDS  training seconds the SFL run is sized for, from the measured transformer throughput (default 30);
#                0 leaves the SFL run out (~4 minutes less: when the device time goes to training instead)
#   KINETIX      the command (default .venv/bin/kinetix); PYTHON likewise
#   EVAL_LEVELS  the SFL run's evaluation suite (default: the paper's s levels if fetched, else levels/s)
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: $0 OUT_DIR" >&2
  exit 2
fi
out=$1
here=$(dirname "$0")
kinetix=${KINETIX:-.venv/bin/kinetix}
python=${PYTHON:-.venv/bin/python}
eval_levels=${EVAL_LEVELS:-levels/s}
[ -z "${EVAL_LEVELS:-}" ] && [ -d .cache/reference-levels/s ] && eval_levels=.cache/reference-levels/s
mkdir -p "$out"

if [ "${TINY:-0}" = 1 ]; then
  engine=(--envs 2,4 --steps 2 --min-time 0.1)
  train=(--steps 8 --epochs 1 --minibatches 2 --width 16 --layers 1 --min-time 0.1)
  envs=8 paper_envs=16
  sfl=(--set ppo.num_envs=8 --set ppo.num_steps=8 --set ppo.update_epochs=1 --set ppo.num_minibatches=2
    --set model.width=16 --set model.actor_critic_layers=1 --set model.transformer_layers=1 --set model.heads=4
    --set curriculum.score_levels=8 --set curriculum.score_batch=8 --set curriculum.score_steps=8
    --set curriculum.buffer_size=4 --set curriculum.refresh_every=2 --set run.eval_attempts=2)
  seconds=${SFL_SECONDS:-0.2}
else
  engine=(--envs 1024,2048,4096,8192,16384 --steps 20 --min-time 1)
  train=(--steps 64 --epochs 8 --minibatches 32 --width 128 --layers 5 --min-time 5)
  envs=2048 paper_envs=32768
  sfl=(--set run.eval_attempts=50)
  seconds=${SFL_SECONDS:-30}
fi

"$kinetix" bench engine --size m "${engine[@]}" --against jax2d --json "$out/engine-m.json"
"$kinetix" bench train --size m --models "${MODELS:-pi-mlp,transformer}" --envs $envs "${train[@]}" \
  --json "$out/train-m.json"
"$kinetix" bench train --size m --models transformer --envs $paper_envs "${train[@]}" --json "$out/train-m-paper.json"
if [ "$seconds" = 0 ]; then
  "$python" "$here/gpu_summary.py" "$out"
  exit 0
fi

# The SFL run: as many updates as the transformer's measured rate fits into $seconds (SFL's scoring comes on top)
steps=$("$python" "$here/gpu_summary.py" --sfl-steps "$out/train-m.json" "$seconds" "${sfl[@]}")
rm -rf "$out/sfl"
start=$(date +%s)
"$kinetix" pretrain --config experiments/pretrain-s.yaml --run-dir "$out/sfl" "${sfl[@]}" \
  --set "ppo.total_timesteps=$steps" --set run.eval_every=0 --set run.checkpoint_every=0
echo "$(($(date +%s) - start))" >"$out/sfl/wall_seconds"
"$kinetix" eval "$out/sfl" --levels "$eval_levels" --attempts "$([ "${TINY:-0}" = 1 ] && echo 2 || echo 50)" \
  --json "$out/sfl/eval.json"
"$python" "$here/gpu_summary.py" "$out"
