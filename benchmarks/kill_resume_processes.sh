#!/usr/bin/env bash
# Two-process training, killed and resumed: for each variant of the cpu-small run (the default generated pool, a
# level set with --levels, SFL, and the PLR config), an uninterrupted 2-process run, then the same run with kill -9 of
# process VICTIM once checkpoint 4 is on disk, then --resume of both processes; the resumed run's parameters and
# metrics must equal the uninterrupted run's (compare_runs below). Prints one line per variant; exit 1 if any differs.
#
#   benchmarks/kill_resume_processes.sh OUT_DIR      VICTIM=1 VARIANTS="pool levelset sfl plr" (defaults)
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: $0 OUT_DIR" >&2
  exit 2
fi
out=$1
kinetix=${KINETIX:-.venv/bin/kinetix}
python=${PYTHON:-.venv/bin/python}
victim=${VICTIM:-1}
mkdir -p "$out"
# 8 updates (of 2,048 steps; PLR's of 8,192: its variant sets its own total, after these), checkpoints every 2; no
# evaluation (it does not change training)
common=(--set ppo.total_timesteps=16384 --set run.checkpoint_every=2 --set run.eval_every=0)
[ -f "$out/set/manifest.json" ] || "$kinetix" generate --size s --count 256 --seed 0 --out "$out/set" >/dev/null

variant_args() {
  case $1 in
    pool) echo "--config experiments/cpu-small.yaml" ;;
    levelset) echo "--config experiments/cpu-small.yaml --levels $out/set" ;;
    sfl) echo "--config experiments/cpu-small.yaml --set curriculum.name=sfl" ;;
    plr) echo "--config experiments/cpu-plr.yaml --set ppo.total_timesteps=65536" ;;  # its updates are 8,192 steps
  esac
}

run_two() {  # run_two RUN_DIR ARGS...: both processes, waited for
  local dir=$1 port
  shift
  port=$($python -c "import socket; s = socket.socket(); s.bind(('localhost', 0)); print(s.getsockname()[1])")
  for p in 0 1; do
    "$kinetix" pretrain "$@" --run-dir "$dir" --coordinator "localhost:$port" --num-processes 2 --process-id $p \
      >"$dir.log$p" 2>&1 &
  done
}

status=0
for variant in ${VARIANTS:-pool levelset sfl plr}; do
  read -r -a args <<<"$(variant_args "$variant")"
  whole=$out/$variant-whole cut=$out/$variant-killed
  rm -rf "$whole" "$cut"
  run_two "$whole" "${common[@]}" "${args[@]}"
  wait
  run_two "$cut" "${common[@]}" "${args[@]}"
  pids=($(jobs -p))
  until [ -f "$cut/checkpoints/4/kinetix-checksums.json" ]; do
    if [ -z "$(jobs -rp)" ]; then echo "$variant: the run ended without checkpoint 4" >&2; exit 1; fi
    sleep 0.05
  done
  kill -9 "${pids[$victim]}"
  wait || true
  if [ -d "$cut/checkpoints/8" ]; then echo "$variant: the run ended before the kill; rerun" >&2; status=1; continue; fi
  echo "$variant: process $victim killed at checkpoint $(ls "$cut/checkpoints" | sort -n | tail -1); the other: $(tail -n 1 "$cut.log$((1 - victim))")"
  run_two "$cut" "${common[@]}" "${args[@]}" --resume
  wait
  if $python - "$whole" "$cut" "$variant" <<'PY'; then :; else status=1; fi
import json, sys
import jax, numpy as np
from kinetix_cli.rl.agents import load_policy
whole, cut, variant = sys.argv[1:]
same = all(np.array_equal(a, b) for a, b in zip(jax.tree.leaves(load_policy(whole).params), jax.tree.leaves(load_policy(cut).params)))
lines = lambda d: [{k: v for k, v in json.loads(x).items() if k != "sps"} for x in open(f"{d}/metrics.jsonl")]
same_metrics = lines(whole) == lines(cut)
print(f"{variant}: killed after checkpoint 4, resumed: params {'equal' if same else 'DIFFER'}, "
      f"metrics {'equal' if same_metrics else 'DIFFER'} ({len(lines(cut))} updates)")
sys.exit(0 if same and same_metrics else 1)
PY
done
exit $status
