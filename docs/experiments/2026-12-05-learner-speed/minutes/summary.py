"""The minutes-to-15.3% table from the files next to this script (run.sh's): each seed's scored checkpoints, the
first at or above general-s v2's 15.3% with its training minutes (README.md's rule), the final score, the run's
minutes, and SFL scoring's share of them (the refresh updates' time beyond a plain update's median); today's code's
seeds (run.sh), v2's own code's (run_v2.sh, run_v2_last.sh), 11c143b's (run_before.sh). Run: python summary.py"""

import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent
BATCH, TARGET, REFRESH_EVERY = 256 * 32, 0.153, 64


def seconds(run: str) -> list[float]:
    """Each update's training seconds, as `run.minutes` counts them (compile and SFL scoring included)."""
    rows = [json.loads(line) for line in (HERE / f"metrics-{run}.jsonl").open() if '"sps"' in line]
    return [BATCH / row["sps"] for row in rows]


def scores(run: str) -> dict[int, float]:
    found = {}
    for path in HERE.glob(f"val-{run}-*.json"):
        record = json.loads(path.read_text())
        found[record["update"]] = record["score"]["zero_shot"]
    return dict(sorted(found.items()))


print(
    "| code, seed | scored checkpoints (update: score) | first at 15.3% | its minutes | final | run minutes "
    "| scoring share |"
)
print("|---|---|---|---|---|---|---|")
reached = []
for run in ["today-0", "today-1", "today-2", "v2-1", "before-1", "v2-2"]:
    if not (HERE / f"metrics-{run}.jsonl").exists():
        continue
    times, scored = seconds(run), scores(run)
    plain = statistics.median(s for i, s in enumerate(times) if i % REFRESH_EVERY)
    scoring = sum(s - plain for i, s in enumerate(times) if i % REFRESH_EVERY == 0 and i > 0)
    first = next((u for u, score in scored.items() if score >= TARGET), None)
    minutes = sum(times[:first]) / 60 if first else None
    if minutes:
        reached.append(minutes)
    cells = [
        run.replace("-", ", seed "),
        ", ".join(f"{u}: {score:.1%}" for u, score in scored.items()),
        f"{first} ({first * BATCH / 1e6:.1f}M steps)" if first else "not reached",
        f"{minutes:.1f}" if minutes else "-",
        f"{scored[len(times)]:.1%}" if len(times) in scored else "-",
        f"{sum(times) / 60:.1f}",
        f"{scoring / sum(times[1:]):.1%}",
    ]
    print("| " + " | ".join(cells) + " |")
if len(reached) == 5:
    print(f"mean minutes to 15.3%: {statistics.mean(reached):.1f} (general-s v2: 58)")
