"""Probe: a shipped agent (default `general`, v3 when run) with its actor logits divided by T, on the held-out
levels or the paper's 74. Run: `python temper-v3.py heldout 20 2000 1.0,0.7,0.5,1.2,1.5 > temper-v3.jsonl`
(levels, attempts, evaluation seed, temperatures); reads runs/heldout/
(benchmarks/general-v3-cpu-2026-11-27/heldout.sh). The same numbers come from the standard path: an agent folder
from benchmarks/general-v3-cpu-2026-11-27/temper.py, then `kinetix eval`;
this probe (the one that ran) skips the folder."""

import json
import sys
from pathlib import Path

from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.evaluate import Evaluator
from kinetix_cli.rl.networks import temper

which, attempts, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
temperatures = [float(t) for t in sys.argv[4].split(",")]
agent = sys.argv[5] if len(sys.argv) > 5 else "general"
root = "runs/heldout" if which == "heldout" else ".cache/reference-levels"
files = sorted(p for size in "sml" for p in Path(root, size).glob("*.json"))
policy = load_policy(agent)
evaluator = Evaluator(policy.config, files, attempts)
for temperature in temperatures:
    results = evaluator(temper(policy.params, temperature), seed)
    by_size = {}
    for r in results:
        by_size.setdefault(r.size, []).append(r.solve_rate)
    rates = [r.solve_rate for r in results]
    row = {"agent": agent, "which": which, "seed": seed, "T": temperature, "mean": sum(rates) / len(rates)}
    print(json.dumps({**row, **{k: sum(v) / len(v) for k, v in by_size.items()}, "n": len(rates)}), flush=True)
