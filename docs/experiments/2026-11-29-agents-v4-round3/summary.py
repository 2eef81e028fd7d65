"""This round's table from the records beside this file: per recipe and seed the validation means (all 180 and each
size's, by the first round's `decide.mean`) and, once test.sh has run (after the decision), the test means (the
paper's 74 levels, seed 1000, by the second round's `summary.test_means`). Run from the checkout's root:
python docs/experiments/2026-11-29-agents-v4-round3/summary.py"""

import importlib.util
import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent


def _load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


round2 = _load("round2_summary", HERE.parent / "2026-11-29-agents-v4-round2" / "summary.py")
decide = round2.decide


def main() -> None:
    print("| recipe | seed | validation all 180 | s | m | l | test all 74 | s | m | l |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for recipe in ("E", "F"):
        rows = []
        for seed in decide.SEEDS:
            record = json.loads((HERE / f"zero-shot-{recipe}-{seed}.json").read_text())
            scores = [decide.mean(record, size) for size in round2.SIZES]
            test = HERE / f"test-{recipe}-{seed}-1000.json"
            scores += round2.test_means(test) if test.exists() else []
            rows.append(scores)
            print(f"| {recipe} | {seed} | " + " | ".join(f"{100 * s:.1f}%" for s in scores) + " |")
        means = " | ".join(
            f"{100 * statistics.mean(c):.1f}% ({100 * statistics.stdev(c):.2f})" for c in zip(*rows, strict=True)
        )
        print(f"| {recipe} | mean (sd) | {means} |")


if __name__ == "__main__":
    main()
