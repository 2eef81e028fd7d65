"""The tables of the protocol study from this folder's records: every candidate's zero-shot validation, the chosen
versions' full validation, and their test evaluations. Run from the checkout's root:
python docs/experiments/2026-11-28-protocol/summary.py"""

import json
from pathlib import Path

FOLDER = Path(__file__).parent
PARTS = [f"levels/validation/{size}" for size in "sml"] + [f"levels/{size}" for size in "sml"]


def pct(x: float) -> str:
    return f"{100 * x:.1f}%"


def main() -> None:
    print("| candidate | held out s / m / l | ours s / m / l | all 180 |")
    print("| --- | --- | --- | --- |")
    for file in sorted(FOLDER.glob("zero-shot-*.json")):
        suites = json.loads(file.read_text())["suites"]
        held, ours = (" / ".join(pct(suites[p]["solve_rate"]) for p in group) for group in (PARTS[:3], PARTS[3:]))
        name = file.stem.removeprefix("zero-shot-").replace("-v", " v")
        print(f"| {name} | {held} | {ours} | {pct(suites['all']['solve_rate'])} |")
    print()
    print("| chosen | zero-shot all 180 | fine-tuned (seeds 0 / 1 / 2) | fine-tuning mean |")
    print("| --- | --- | --- | --- |")
    for file in sorted(FOLDER.glob("validation-*.json")):
        record = json.loads(file.read_text())
        tuned = "; ".join(
            f"{Path(level).stem} " + " / ".join(pct(r) for r in row["solve_rate"])
            for level, row in record["finetune"]["levels"].items()
        )
        name = file.stem.removeprefix("validation-").replace("-v", " v")
        print(f"| {name} | {pct(record['score']['zero_shot'])} | {tuned} | {pct(record['score']['finetune'])} |")
    print()
    print("| chosen | test seed | s | m | l | all 74 |")
    print("| --- | --- | --- | --- | --- | --- |")
    for file in sorted(FOLDER.glob("test-*.json")):
        record = json.loads(file.read_text())
        suites = record["suites"]
        sizes = " | ".join(pct(suites[f".cache/reference-levels/{size}"]["solve_rate"]) for size in "sml")
        name = file.stem.removeprefix("test-").rsplit("-", 1)[0].replace("-v", " v")
        print(f"| {name} | {record['seed']} | {sizes} | {pct(suites['all']['solve_rate'])} |")


if __name__ == "__main__":
    main()
