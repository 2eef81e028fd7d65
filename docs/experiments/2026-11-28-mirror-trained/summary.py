"""The trained-equivariance table: per arm (plain: the batch-scale study's 256 arm at 3M env steps; geometric:
model.mirror) and seed, the validation mean (all 180, per size), the plain runs' gap to the mirror images, the test
mean (the paper's 74 levels, read after the decision), training wall time; per arm mean and standard deviation over
seeds 0-2, and over seeds 0-3 once the fresh clone's seed 3 (`seed3.sh`) is recorded. Then the same at equal
wall-clock (10 minutes of training each). Run from the repository root."""

from __future__ import annotations

import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent
BASE = HERE.parent / "2026-11-28-batch-scale"
# (arm, seed) -> (folder, record stem, test record or None); seed 3 of both arms lives here (fresh clone)
RUNS = {
    **{("plain", s): (BASE, f"steps-256-{s}", BASE / f"test-steps-256-{s}.json") for s in (0, 1, 2)},
    **{("geometric", s): (HERE, f"geometric-{s}", HERE / f"test-geometric-{s}.json") for s in (0, 1, 2)},
    ("plain", 3): (HERE, "plain-3", None),
    ("geometric", 3): (HERE, "geometric-3", None),
}


def rates(path: Path) -> dict[tuple[str, str], float]:
    return {(r["size"], Path(r["level"]).stem): r["solve_rate"] for r in json.loads(path.read_text())["levels"]}


def spread(values: list[float]) -> str:
    sd = statistics.stdev(values) if len(values) > 1 else float("nan")
    return f"mean {statistics.mean(values):.2f}%, sd {sd:.2f} over {len(values)} seeds"


def main() -> None:
    print("| arm | seed | all 180 | s | m | l | mean gap to mirror image | test, all 74 | training wall time |")
    print("|---|---|---|---|---|---|---|---|---|")
    means: dict[tuple[str, bool], list[float]] = {}
    tests: dict[str, list[float]] = {}
    for (arm, seed), (folder, stem, test) in RUNS.items():
        record = folder / f"{stem}.json"
        if not record.is_file():
            continue
        result = rates(record)
        sizes = [100 * statistics.mean(v for (z, _), v in result.items() if z == size) for size in "sml"]
        gap = ""
        image = HERE / f"plain-{seed}-mirrorimage.json"
        if arm == "plain" and image.is_file():
            mirrored = rates(image)
            gap = f"{100 * statistics.mean(abs(result[k] - mirrored[k]) for k in result):.1f}"
        test_mean = ""
        if test is not None and test.is_file():
            value = 100 * statistics.mean(rates(test).values())
            test_mean = f"{value:.1f}%"
            tests.setdefault(arm, []).append(value)
        wall = float((folder / f"{stem}.time").read_text().split()[0])
        total = 100 * statistics.mean(result.values())
        if seed < 3:
            means.setdefault((arm, False), []).append(total)
        means.setdefault((arm, True), []).append(total)
        cells = " | ".join(f"{x:.1f}%" for x in sizes)
        print(f"| {arm} | {seed} | {total:.1f}% | {cells} | {gap} | {test_mean} | {wall:.0f} s |")
    print()
    for (arm, with_fourth), values in means.items():
        if not with_fourth or len(values) == 4:
            print(f"{arm}, {'seeds 0-3' if with_fourth else 'seeds 0-2'}: {spread(values)}")
    for arm, values in tests.items():
        print(f"test, {arm}: {spread(values)}")
    wall_clock()


def wall_clock() -> None:
    """The equal-wall-clock table (10 minutes of training; the batch-scale study's part 2 ran both arms)."""
    print("\n| arm, 10 minutes | seed | env steps | all 180 | s | m | l | test, all 74 |")
    print("|---|---|---|---|---|---|---|---|")
    means: dict[str, list[float]] = {}
    for arm, stem in (("plain", "minutes-256"), ("geometric", "minutes-mirror")):
        for seed in (0, 1, 2):
            record = BASE / f"{stem}-{seed}.json"
            if not record.is_file():
                continue
            result = rates(record)
            sizes = " | ".join(
                f"{100 * statistics.mean(v for (z, _), v in result.items() if z == size):.1f}%" for size in "sml"
            )
            lines = (BASE / f"{stem}-{seed}.metrics.jsonl").read_text().splitlines()
            steps = json.loads(lines[-1])["steps"] / 1e6
            test = BASE / f"test-{stem}-{seed}.json"
            test_mean = f"{100 * statistics.mean(rates(test).values()):.1f}%" if test.is_file() else ""
            total = 100 * statistics.mean(result.values())
            means.setdefault(arm, []).append(total)
            print(f"| {arm} | {seed} | {steps:.2f}M | {total:.1f}% | {sizes} | {test_mean} |")
    print()
    for arm, values in means.items():
        print(f"{arm}, 10 minutes: {spread(values)}")


if __name__ == "__main__":
    main()
