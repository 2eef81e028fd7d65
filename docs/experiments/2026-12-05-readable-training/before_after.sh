#!/usr/bin/env bash
# Before and after the training loop's split, in one run, alternating: `kinetix bench train` (the jitted update) and
# a short `kinetix pretrain` of the shipped recipe (the whole loop: recorder, metrics, checkpoints), each tree with
# its own .venv. BEFORE and AFTER are checkouts (default: a clone of 6f4fdc3 and this one); OUT gets the JSON and
# metrics files.
set -euo pipefail
BEFORE=${BEFORE:?a checkout of the code before (6f4fdc3) with its .venv}
AFTER=${AFTER:-$(cd "$(dirname "$0")/../../.." && pwd)}
OUT=${OUT:-$(pwd)/before-after}
mkdir -p "$OUT"
for round in 1 2; do
  for side in before after; do
    tree=$BEFORE; [ "$side" = after ] && tree=$AFTER
    (cd "$tree" && .venv/bin/kinetix bench train --size s --models pi-mlp,rel-mlp --envs 64 --width 64 --layers 3 \
      --min-time 10 --json "$OUT/bench-$side-$round.json" > "$OUT/bench-$side-$round.txt" 2>&1)
    rm -rf "$OUT/run-$side-$round"
    (cd "$tree" && .venv/bin/kinetix pretrain --config experiments/general.yaml --run-dir "$OUT/run-$side-$round" \
      --set ppo.total_timesteps=262144 --set run.eval_every=0 --set run.checkpoint_every=8 > /dev/null 2>&1)
    cp "$OUT/run-$side-$round/metrics.jsonl" "$OUT/metrics-$side-$round.jsonl"
    rm -rf "$OUT/run-$side-$round"
  done
done
python3 - "$OUT" <<'PY'
import json, statistics, sys, pathlib
out = pathlib.Path(sys.argv[1])
for side in ("before", "after"):
    for round in (1, 2):
        bench = json.loads((out / f"bench-{side}-{round}.json").read_text())
        rows = bench["results"] if isinstance(bench, dict) and "results" in bench else bench
        lines = [json.loads(x) for x in (out / f"metrics-{side}-{round}.jsonl").read_text().splitlines()]
        steady = statistics.median(r["sps"] for r in lines[1:])
        print(side, round, "pretrain steady SPS (median of updates 2-32):", round_ := f"{steady:,.0f}",
              "first update s:", f"{8192 / lines[0]['sps']:.1f}")
        print("  bench:", json.dumps(rows)[:600])
PY
