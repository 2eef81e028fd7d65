#!/usr/bin/env bash
# Ours vs the reference Kinetix PPO update with each side's entity transformer (issue 70, part 5): size s, 256 envs x
# 32 steps, 4 epochs x 4 minibatches, 1 CPU device each, alternating ours, ref, ours, ref; one at a time. The two
# transformers are each project's own (ours: `kinetix bench train --models transformer --width 64 --layers 3`; the
# reference: its configs/model/model-transformer.yaml), so each row also gives XLA's FLOP count of its update.
# Results: ours-transformer-N.json, ref-transformer-N.json and side_by_side_transformer.log in this folder.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../../../.." && pwd)"
REF_PY="$ROOT/.cache/reference-venv/bin/python"
ARGS_COMMON=(--envs 256 --steps 32 --epochs 4 --minibatches 4 --width 64 --layers 3 --min-time 20)
exec > >(tee "$HERE/side_by_side_transformer.log") 2>&1
echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ) nproc: $(nproc)"
echo "ours jax: $("$ROOT/.venv/bin/python" -c 'import jax, jaxlib; print(jax.__version__, jaxlib.__version__)')"
echo "ref  jax: $("$REF_PY" -c 'import jax, jaxlib; print(jax.__version__, jaxlib.__version__)')"
export KINETIX_COMPILE_CACHE=off  # both compile times are real compiles
for round in 1 2; do
  echo "== round $round: ours $(date -u +%T)"
  "$ROOT/.venv/bin/kinetix" bench train --models transformer --size s "${ARGS_COMMON[@]}" --devices 1 \
    --json "$HERE/ours-transformer-$round.json"
  echo "== round $round: reference $(date -u +%T)"
  "$REF_PY" "$HERE/reference_ppo.py" "${ARGS_COMMON[@]}" --model transformer --json "$HERE/ref-transformer-$round.json"
done
echo "done: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
