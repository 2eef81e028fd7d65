"""This round's table from the records beside this file: per recipe and seed, the PPO updates and env steps trained,
the training wall time, the validation means (all 180 and each size's, by the first round's `decide.mean`) and, once
test.sh has run (after the decision), the test means (the paper's 74 levels, seed 1000). Run from the checkout's
root: python docs/experiments/2026-11-29-agents-v4-round2/summary.py; the fourth round's (a folder of runs alike):
summary.py docs/experiments/2026-11-29-agents-v4-round4 G"""

import gzip
import importlib.util
import json
import statistics
import sys
from pathlib import Path

HERE = Path(__file__).parent
_spec = importlib.util.spec_from_file_location("decide", HERE.parent / "2026-11-28-agents-v4" / "decide.py")
decide = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(decide)
SIZES = (None, "s", "m", "l")


def test_means(path: Path) -> list[float]:
    """All 74 levels and each size's (`.cache/reference-levels/X`), from a `kinetix eval --json` file."""
    suites = json.loads(path.read_text())["suites"]
    return [suites["all" if size is None else f".cache/reference-levels/{size}"]["solve_rate"] for size in SIZES]


def main(folder: Path = HERE, recipes: tuple[str, ...] = ("C", "D")) -> None:
    print("| recipe | seed | updates | env steps | wall | validation all 180 | s | m | l | test all 74 | s | m | l |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for recipe in recipes:
        rows = []
        for seed in decide.SEEDS:
            metrics = gzip.decompress((folder / f"{recipe}-{seed}.metrics.jsonl.gz").read_bytes()).decode()
            last = json.loads(metrics.splitlines()[-1])
            wall = float((folder / f"{recipe}-{seed}.time").read_text().split()[0])
            record = json.loads((folder / f"zero-shot-{recipe}-{seed}.json").read_text())
            scores = [decide.mean(record, size) for size in SIZES]
            test = folder / f"test-{recipe}-{seed}-1000.json"
            scores += test_means(test) if test.exists() else []
            rows.append(scores)
            cells = " | ".join(f"{100 * s:.1f}%" for s in scores)
            print(f"| {recipe} | {seed} | {last['update']} | {last['steps'] / 1e6:.2f}M | {wall:.0f} s | {cells} |")
        means = " | ".join(
            f"{100 * statistics.mean(c):.1f}% ({100 * statistics.stdev(c):.2f})" for c in zip(*rows, strict=True)
        )
        print(f"| {recipe} | mean (sd) | | | | {means} |")


if __name__ == "__main__":
    main(Path(sys.argv[1]), tuple(sys.argv[2:])) if len(sys.argv) > 2 else main()
