"""The round's learning curve: every copy on the validation suite (all 180 and per size), per seed and, where all
three seeds have it, their mean and sd; once test.sh has run (after the decision), each copy's test columns too (the
paper's 74 levels, seed 1000). Reads only this folder's records. From the checkout's root:
python docs/experiments/2026-11-30-agents-v4-round7/curve.py"""

import json
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[1] / "2026-11-28-agents-v4"))
sys.path.insert(0, str(Path(__file__).parents[1] / "2026-11-29-agents-v4-round2"))
from decide import mean  # noqa: E402  (the study scripts are not a package)
from summary import test_means  # noqa: E402

FOLDER = Path(__file__).parent
MINUTES = (60, 120, 180, 240)
SEEDS = (20, 21, 22)
SIZES = (None, "s", "m", "l")
STEPS_PER_UPDATE = 256 * 32  # experiments/general.yaml: envs x steps


def main() -> None:
    tested = any(FOLDER.glob("test-K*-1000.json"))
    head = "| training minutes | seed | updates | env steps | validation, all 180 | s (50) | m (60) | l (70) |"
    print(head + (" test, all 74 | s | m | l |" if tested else ""))
    print("|---" * (12 if tested else 8) + "|")
    for minutes in MINUTES:
        scores = []
        for seed in SEEDS:
            path = FOLDER / f"zero-shot-K{minutes}-{seed}.json"
            if not path.exists():
                continue
            record = json.loads(path.read_text())
            row = [mean(record, size) for size in SIZES]
            if tested:
                row += test_means(FOLDER / f"test-K{minutes}-{seed}-1000.json")
            scores.append(row)
            cells = " | ".join(f"{100 * s:.1f}%" for s in row)
            steps = record["update"] * STEPS_PER_UPDATE
            print(f"| {minutes} | {seed} | {record['update']:,} | {steps / 1e6:.1f}M | {cells} |")
        if len(scores) == len(SEEDS):
            cells = " | ".join(
                f"{100 * statistics.mean(col):.1f}% ({100 * statistics.stdev(col):.2f})"
                for col in zip(*scores, strict=True)
            )
            print(f"| {minutes} | mean (sd) | | | {cells} |")


if __name__ == "__main__":
    main()
