"""Which of the validation suite's held-out levels carry signal: per size, how many the search solves
(`runs/validation-solved/<size>`, from run.sh) and how many no agent has ever solved zero-shot, over every
validation record (`kinetix-validation/1`) committed under docs/experiments/ (each agent or run that was validated,
50 attempts, seed 1000). Reads no test level. Run from the checkout's root after run.sh:
.venv/bin/python docs/experiments/2026-11-30-validation-signal/dead_levels.py"""

import json
from pathlib import Path

from kinetix_cli.levels.levelset import load_levelset
from kinetix_cli.levels.suites import SUITES

RECORDS = Path("docs/experiments")


def best_agent_rates() -> tuple[int, dict[str, float]]:
    """(records read, each validation level's best zero-shot solve rate over them)."""
    best: dict[str, float] = {}
    count = 0
    for path in sorted(RECORDS.rglob("*.json")):
        try:
            record = json.loads(path.read_text())
        except (UnicodeDecodeError, json.JSONDecodeError):
            continue
        if not isinstance(record, dict) or record.get("format") != "kinetix-validation/1":
            continue
        count += 1
        for level in record["levels"]:
            best[level["level"]] = max(best.get(level["level"], 0.0), level["solve_rate"])
    return count, best


def main() -> None:
    count, best = best_agent_rates()
    print(f"{count} validation records")
    print(
        "| size | held-out levels | solved by the search | solved by no agent | of those, by the search |"
        " solved by an agent, not by the search |"
    )
    print("|---|---|---|---|---|---|")
    for size in SUITES:
        solved = load_levelset(Path("runs/validation-solved") / size).solutions.solved
        rates = [best[f"levels/validation/{size}/validation-{size}-{i:03d}.json"] for i in range(len(solved))]
        dead = [i for i, rate in enumerate(rates) if rate == 0.0]
        searched = sum(bool(solved[i]) for i in dead)
        agent_only = sum(1 for i, rate in enumerate(rates) if rate > 0.0 and not solved[i])
        print(f"| {size} | {len(solved)} | {int(solved.sum())} | {len(dead)} | {searched} | {agent_only} |")
    ours = {name: rate for name, rate in best.items() if not name.startswith("levels/validation/")}
    print(f"our levels: {len(ours)}, solved by no agent: {sum(rate == 0.0 for rate in ours.values())}")


if __name__ == "__main__":
    main()
