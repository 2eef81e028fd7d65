"""The batch-scale table from the records beside this file: per arm and seed, the validation mean (all 180 and the
50 s levels) and the training wall time; per arm the mean and standard deviation over seeds.
Run from the repository root: python docs/experiments/2026-11-28-batch-scale/summary.py"""

from __future__ import annotations

import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent


def main() -> None:
    print("| envs per update | seed | updates | validation, all 180 | s (50) | training wall time |")
    print("|---|---|---|---|---|---|")
    means = {}
    for envs in (256, 1024, 4096):
        for seed in (0, 1, 2):
            record = HERE / f"steps-{envs}-{seed}.json"
            if not record.is_file():
                continue
            levels = json.loads(record.read_text())["levels"]
            all_levels = 100 * statistics.mean(r["solve_rate"] for r in levels)
            s = 100 * statistics.mean(r["solve_rate"] for r in levels if r["size"] == "s")
            wall = (HERE / f"steps-{envs}-{seed}.time").read_text().split()[0]
            updates = 3_000_000 // (envs * 32)
            print(f"| {envs:,} | {seed} | {updates} | {all_levels:.1f}% | {s:.1f}% | {float(wall):.0f} s |")
            means.setdefault(envs, []).append(all_levels)
    for envs, values in means.items():
        spread = statistics.stdev(values) if len(values) > 1 else float("nan")
        print(f"\n{envs:,} envs: mean {statistics.mean(values):.2f}%, sd {spread:.2f} over {len(values)} seeds")


if __name__ == "__main__":
    main()
