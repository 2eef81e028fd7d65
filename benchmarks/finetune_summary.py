"""Summarise benchmarks/finetune_vs_scratch.sh: per level and arm, the final solve rate of each seed and the
evaluation curve during training (mean over seeds). Usage: python3 finetune_summary.py OUT_DIR"""

import json
import statistics
import sys
from pathlib import Path

out = Path(sys.argv[1])
print("| level | arm | final solve rate per seed | mean | eval solve rate during training (mean over seeds) |")
print("|---|---|---|---|---|")
totals = {}  # arm -> per level (mean final, mean of the curve)
for level in sorted(p for p in out.iterdir() if p.is_dir()):
    arms = sorted({r.name.rsplit("-", 1)[0] for r in level.iterdir() if r.is_dir()})  # finetuned, scratch, others
    for arm in arms:
        runs = sorted(r for r in level.glob(f"{arm}-*") if (r / "eval.json").exists())  # finished runs
        finals = [json.loads((r / "eval.json").read_text())["suites"]["all"]["solve_rate"] for r in runs]
        curves = {}
        for r in runs:
            for line in (r / "metrics.jsonl").read_text().splitlines():
                record = json.loads(line)
                if "eval_solve_rate" in record:
                    curves.setdefault(record["steps"], []).append(record["eval_solve_rate"])
        curve = ", ".join(f"{steps // 1000}K: {statistics.mean(v):.0%}" for steps, v in sorted(curves.items()))
        seeds = " / ".join(f"{f:.0%}" for f in finals)
        mean = statistics.mean(finals) if finals else float("nan")
        print(f"| {level.name} | {arm} | {seeds} | {mean:.0%} | {curve} |")
        if finals and curves:
            area = statistics.mean(statistics.mean(v) for v in curves.values())
            totals.setdefault(arm, []).append((mean, area))
print()
for arm, rows in sorted(totals.items()):
    finals, areas = zip(*rows, strict=True)
    final, area = statistics.mean(finals), statistics.mean(areas)
    print(f"- {arm}: {len(rows)} levels, mean final {final:.1%}, mean of the curves {area:.1%}")
