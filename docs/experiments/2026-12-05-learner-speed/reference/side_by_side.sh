#!/usr/bin/env bash
# Ours vs the reference Kinetix PPO update, same numbers, alternating ours, ref, ours, ref; one at a time.
# Run from anywhere on an otherwise idle machine: bash docs/experiments/2026-12-05-learner-speed/reference/side_by_side.sh
# Results: ours-1.json, ref-1.json, ours-2.json, ref-2.json in this folder, plus side_by_side.log.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../../../.." && pwd)"
OURS="$ROOT/.venv/bin/kinetix"
REF_PY="$ROOT/.cache/reference-venv/bin/python"
# Ours reads compiled programs from a persistent disk cache by default; off here so both compile times are real
# compiles. Run with OURS_COMPILE_CACHE=on to keep ours' default.
OURS_COMPILE_CACHE="${OURS_COMPILE_CACHE:-off}"
ARGS_COMMON=(--envs 256 --steps 32 --epochs 4 --minibatches 4 --width 64 --layers 3 --min-time 10)

exec > >(tee "$HERE/side_by_side.log") 2>&1
echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
echo "nproc: $(nproc)"
echo "ours jax: $("$ROOT/.venv/bin/python" -c 'import jax, jaxlib; print(jax.__version__, jaxlib.__version__)')"
echo "ref  jax: $("$REF_PY" -c 'import jax, jaxlib; print(jax.__version__, jaxlib.__version__)')"
echo "ours compile cache: $OURS_COMPILE_CACHE; KINETIX_CPU_DEVICES=${KINETIX_CPU_DEVICES:-<unset>}"
echo "ref  kinetix-env: $("$REF_PY" -c 'import importlib.metadata as m; print(m.version("kinetix-env"))')"

for round in 1 2; do
  echo "== round $round: ours =="
  if [ "$OURS_COMPILE_CACHE" = off ]; then export KINETIX_COMPILE_CACHE=off; else unset KINETIX_COMPILE_CACHE; fi
  "$OURS" bench train --models flat-mlp --size s "${ARGS_COMMON[@]}" --devices 1 --json "$HERE/ours-$round.json"
  echo "== round $round: reference =="
  "$REF_PY" "$HERE/reference_ppo.py" "${ARGS_COMMON[@]}" --model mlp --json "$HERE/ref-$round.json"
done
echo "done: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
