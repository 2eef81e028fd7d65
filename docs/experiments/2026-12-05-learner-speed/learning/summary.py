"""The learning tables from the files next to this script: each run's training time and env steps (metrics-*.jsonl)
and each checkpoint's validation score (val-*.json, all 180 levels zero-shot). The first is `run.sh`'s (before and
after), the second `run_today.sh`'s (the before runs again, for their minutes, and today's code). Run: python
summary.py"""

import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent
BATCH = 256 * 32


def seconds(name: str) -> list[float]:
    """Each update's training seconds, as `run.minutes` counts them (compile and SFL scoring included)."""
    rows = [json.loads(line) for line in (HERE / f"metrics-{name}.jsonl").open() if '"sps"' in line]
    return [BATCH / row["sps"] for row in rows]


def budget_end(times: list[float], minutes: float) -> int:
    """The update during which the training time passed `minutes` (the run's last under that budget)."""
    total = 0.0
    for update, s in enumerate(times, 1):
        total += s
        if total >= minutes * 60:
            return update
    return len(times)


def score(name: str, update: int) -> str:
    path = HERE / f"val-{name}-{update}.json"
    return f"{json.loads(path.read_text())['score']['zero_shot'] * 100:.1f}%" if path.exists() else "-"


def plain_median(times: list[float]) -> float:
    """The median update without SFL scoring (it scores before updates 0, 64, 128, ...)."""
    return statistics.median(s for i, s in enumerate(times) if i % 64)


def same_learning(name: str, other: str) -> bool:
    """Whether two runs' metrics agree in everything but their speed (the same updates, bit for bit)."""

    def rows(run: str) -> list[dict]:
        lines = (HERE / f"metrics-{run}.jsonl").open()
        return [{k: v for k, v in json.loads(line).items() if k != "sps"} for line in lines]

    return rows(name) == rows(other)


def today() -> None:
    print(
        "| seed | before again: minutes, median s, same as before | at 768 "
        "| today: first s, median s | at 768 | at its end |"
    )
    print("| --- | --- | --- | --- | --- | --- |")
    for seed in range(3):
        if not (HERE / f"metrics-today-{seed}.jsonl").exists():
            continue
        before, run = seconds(f"before-again-{seed}"), seconds(f"today-{seed}")
        minutes = sum(before) / 60
        end = budget_end(run, minutes)
        same = "yes" if same_learning(f"before-again-{seed}", f"before-{seed}") else "NO"
        print(
            f"| {seed} | {minutes:.2f}, {plain_median(before):.3f}, {same} | {score(f'before-{seed}', 768)} "
            f"| {run[0]:.1f}, {plain_median(run[:end]):.3f} | {score(f'today-{seed}', 768)} "
            f"| {score(f'today-{seed}', end)} (update {end}, {end * BATCH / 1e6:.2f}M steps) |"
        )


def main() -> None:
    print(
        "| seed | before: minutes, first update s, median s | at 768 | after: first s, median s | at 768 | at its end |"
    )
    print("| --- | --- | --- | --- | --- | --- |")
    for seed in range(3):
        before, after = seconds(f"before-{seed}"), seconds(f"after-{seed}")
        minutes = sum(before) / 60
        end = budget_end(after, minutes)
        print(
            f"| {seed} | {minutes:.2f}, {before[0]:.1f}, {plain_median(before):.3f} | {score(f'before-{seed}', 768)} "
            f"| {after[0]:.1f}, {plain_median(after[:end]):.3f} | {score(f'after-{seed}', 768)} "
            f"| {score(f'after-{seed}', end)} (update {end}, {end * BATCH / 1e6:.2f}M steps) |"
        )


if __name__ == "__main__":
    main()
    print()
    today()
