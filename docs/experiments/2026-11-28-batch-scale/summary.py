"""The batch-scale tables from the records beside this file: per arm and seed, the updates and env steps trained,
the steady-state env steps per second (median over the updates after the first two, SFL scoring included), the
validation mean (all 180 and the 50 s levels), the test mean (the paper's 74 levels, read after the decision) and the
training wall time; per arm the mean and standard deviation over seeds. Part 1 (`steps-*`, equal env steps) and
part 2 (`minutes-*`, equal wall-clock), where recorded.
Run from the repository root: python docs/experiments/2026-11-28-batch-scale/summary.py"""

from __future__ import annotations

import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent
PARTS = {"steps": "part 1, 3M env steps", "minutes": "part 2, 10 minutes of training"}
ARMS = ("256", "1024", "4096", "mirror")


def main() -> None:
    for part, title in PARTS.items():
        rows, means, tests = [], {}, {}
        for arm in ARMS:
            for seed in (0, 1, 2):
                record = HERE / f"{part}-{arm}-{seed}.json"
                if not record.is_file():
                    continue
                levels = json.loads(record.read_text())["levels"]
                all_levels = 100 * statistics.mean(r["solve_rate"] for r in levels)
                s = 100 * statistics.mean(r["solve_rate"] for r in levels if r["size"] == "s")
                wall = float((HERE / f"{part}-{arm}-{seed}.time").read_text().split()[0])
                lines = (HERE / f"{part}-{arm}-{seed}.metrics.jsonl").read_text().splitlines()
                metrics = [json.loads(line) for line in lines]
                sps = statistics.median(m["sps"] for m in metrics[2:])
                name = "256, model.mirror=geometric" if arm == "mirror" else f"{int(arm):,}"
                test = HERE / f"test-{part}-{arm}-{seed}.json"
                test_mean = ""
                if test.is_file():
                    value = 100 * statistics.mean(r["solve_rate"] for r in json.loads(test.read_text())["levels"])
                    test_mean = f"{value:.1f}%"
                    tests.setdefault(name, []).append(value)
                rows.append(
                    f"| {name} | {seed} | {len(metrics)} | {metrics[-1]['steps'] / 1e6:.2f}M | {sps:,.0f} | "
                    f"{all_levels:.1f}% | {s:.1f}% | {test_mean} | {wall:.0f} s |"
                )
                means.setdefault(name, []).append(all_levels)
        if not rows:
            continue
        print(f"\n{title}\n")
        print(
            "| envs per update | seed | updates | env steps | env steps/s | validation, all 180 | s (50) "
            "| test, all 74 | wall time |"
        )
        print("|---|---|---|---|---|---|---|---|---|")
        print("\n".join(rows))
        for name, values in means.items():
            spread = statistics.stdev(values) if len(values) > 1 else float("nan")
            print(f"\n{name}: mean {statistics.mean(values):.2f}%, sd {spread:.2f} over {len(values)} seeds")
        for name, values in tests.items():
            spread = statistics.stdev(values) if len(values) > 1 else float("nan")
            print(f"test, {name}: mean {statistics.mean(values):.2f}%, sd {spread:.2f} over {len(values)} seeds")


if __name__ == "__main__":
    main()
