"""The one-epoch study's tables from the files next to this script: the speed run (SIDE-ROUND.json) and the
learning runs (metrics-epoch-SEED.jsonl, val-epoch-SEED-UPDATE.json, metrics-drift.jsonl). Run: python summary.py"""

import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent
BATCH = 256 * 32
SIDES = {
    "before": "11c143b (4 x 4, 1 device)",
    "sides": "41af707 (4 x 4)",
    "head": "HEAD (4 x 4)",
    "A": "HEAD, 1 epoch x 16",
    "B": "HEAD, 1 x 8",
    "C": "HEAD, 1 x 4",
}
BEFORE_768 = {0: 12.6, 1: 10.8, 2: 10.3}  # ../learning/: 11c143b at 768 updates
BUDGET = {0: 10.31, 1: 10.21, 2: 10.40}  # ../learning/: 11c143b's minutes for them ("before again")


def speed() -> None:
    rates = {
        (s, r): json.loads((HERE / f"{s}-{r}.json").read_text())["results"][0]["steps_per_s"]
        for s in SIDES
        for r in (1, 2)
        if (HERE / f"{s}-{r}.json").exists()
    }
    print("| rel-mlp 64, s, 256 envs | round 1 | round 2 |\n| --- | --- | --- |")
    for side, label in SIDES.items():
        cells = [
            f"{rates[side, r]:,.0f} ({rates[side, r] / rates['before', r]:.2f}x)" for r in (1, 2) if (side, r) in rates
        ]
        print(f"| {label} | " + " | ".join(cells) + " |")


def seconds(name: str) -> list[float]:
    rows = [json.loads(line) for line in (HERE / f"metrics-{name}.jsonl").open() if '"sps"' in line]
    return [BATCH / row["sps"] for row in rows]


def plain_median(times: list[float]) -> float:
    """The median update without SFL scoring (it scores before updates 1, 65, 129, ...)."""
    return statistics.median(s for i, s in enumerate(times) if i % 64)


def score(seed: int, update: int) -> float | None:
    path = HERE / f"val-epoch-{seed}-{update}.json"
    return json.loads(path.read_text())["score"]["zero_shot"] * 100 if path.exists() else None


def learning() -> None:
    if (HERE / "metrics-drift.jsonl").exists():
        print(f"drift: 11c143b's plain update tonight {plain_median(seconds('drift')):.3f} s (0.715-0.722 s then)")
    print("| seed | 11c143b at 768 | 1 epoch at 768 | 1 epoch at the budget's end | updates, plain update, SFL share |")
    print("| --- | --- | --- | --- | --- |")
    at, end = [], []
    for seed in range(3):
        if not (HERE / f"metrics-epoch-{seed}.jsonl").exists():
            continue
        times = seconds(f"epoch-{seed}")
        last = len(times)
        sfl = sum(times[i] - plain_median(times) for i in range(64, last, 64)) / sum(times[1:])  # as ../minutes/
        a, e = score(seed, 768), score(seed, last)
        at.append(a), end.append(e)
        fmt = lambda v: "-" if v is None else f"{v:.1f}%"  # noqa: E731
        print(
            f"| {seed} | {BEFORE_768[seed]:.1f}% | {fmt(a)} | {fmt(e)} | {last:,} ({last * BATCH / 1e6:.2f}M steps), "
            f"{plain_median(times):.3f} s, {sfl:.1%} |"
        )
    if at and None not in at + end:
        print(
            f"| mean | {statistics.mean(BEFORE_768.values()):.1f}% | {statistics.mean(at):.1f}% | "
            f"{statistics.mean(end):.1f}% | |"
        )


if __name__ == "__main__":
    speed()
    learning()
