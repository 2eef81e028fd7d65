"""The lever-4 table from the evaluation records beside this file: per agent and mode, the mean solve rate over the
180 validation levels and per size, and the mean per-level gap between a level and its mirror image (plain runs).
Run from the repository root: python docs/experiments/2026-11-28-mirror/summary.py"""

from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).parent


def rates(name: str) -> dict[tuple[str, str], float] | None:
    path = HERE / f"{name}.json"
    if not path.is_file():
        return None
    levels = json.loads(path.read_text())["levels"]
    return {(row["size"], Path(row["level"]).stem): row["solve_rate"] for row in levels}


def mean(values) -> float:
    values = list(values)
    return 100.0 * sum(values) / len(values)


def main() -> None:
    print("| agent | seed | run | all 180 | s | m | l | mean gap to mirror image |")
    print("|---|---|---|---|---|---|---|---|")
    for agent in ("general", "general-s", "general-m", "general-l"):
        for seed in (1000, 1001):
            plain = rates(f"{agent}-plain-{seed}")
            image = rates(f"{agent}-mirrorimage-{seed}")
            for run in ("plain", "mirrorimage", "mean", "geometric", "value"):
                result = rates(f"{agent}-{run}-{seed}")
                if result is None:
                    continue
                sizes = [f"{mean(v for (z, _), v in result.items() if z == size):.1f}" for size in "sml"]
                gap = ""
                if run == "plain" and image is not None:
                    gap = f"{mean(abs(plain[key] - image[key]) for key in plain):.1f}"
                print(f"| {agent} | {seed} | {run} | {mean(result.values()):.1f} | {' | '.join(sizes)} | {gap} |")


if __name__ == "__main__":
    main()
