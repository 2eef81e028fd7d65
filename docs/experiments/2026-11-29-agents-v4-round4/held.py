"""RERUN.md's test: the rules of the third and fourth rounds' PLAN.md applied to training seeds 0-3 (seed 3 from the
fresh clone, `rerun-zero-shot-X-3.json`): each recipe's four-seed mean and sd per name, and whether any beats the
shipped version by more than max(1.0 point, sd). Run from the checkout's root:
python docs/experiments/2026-11-29-agents-v4-round4/held.py
and for a later round's re-run, its recipe and folder:
python docs/experiments/2026-11-29-agents-v4-round4/held.py H=docs/experiments/2026-11-29-agents-v4-round5"""

import importlib.util
import json
import statistics
import sys
from pathlib import Path

HERE = Path(__file__).parent
_spec = importlib.util.spec_from_file_location("decide", HERE.parent / "2026-11-28-agents-v4" / "decide.py")
decide = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(decide)
ROUNDS = {"E": HERE.parent / "2026-11-29-agents-v4-round3", "F": HERE.parent / "2026-11-29-agents-v4-round3", "G": HERE}
ROUND2 = HERE.parent / "2026-11-29-agents-v4-round2"


def shipped(name: str) -> tuple[str | None, float]:
    """The levels `name` is judged on and its shipped version's score there, from the records the plans name."""
    size, version = decide.SHIPPED[name]
    path = decide.PROTOCOL / f"zero-shot-{name}-{version}.json"
    if name == "general-m":  # v3 since the second round
        path = ROUND2 / "zero-shot-D-2.json"
    return size, decide.mean(json.loads(path.read_text()), size)


def scores(folder: Path, recipe: str, size: str | None) -> list[float]:
    paths = [folder / f"zero-shot-{recipe}-{seed}.json" for seed in (0, 1, 2)]
    paths.append(folder / f"rerun-zero-shot-{recipe}-3.json")
    return [decide.mean(json.loads(p.read_text()), size) for p in paths]


def main(rounds: dict[str, Path] = ROUNDS) -> None:
    beaten = []
    for name in decide.SHIPPED:
        size, score = shipped(name)
        for recipe, folder in rounds.items():
            values = scores(folder, recipe, size)
            avg, sd = statistics.mean(values), statistics.stdev(values)
            wins = avg - score > max(decide.MARGIN, sd)
            seeds = " / ".join(f"{100 * v:.1f}" for v in values)
            print(
                f"{name} ({size or 'all'}): {recipe} seeds 0-3 {seeds}%, mean {100 * avg:.2f}% (sd {100 * sd:.2f})"
                f" against {100 * score:.2f}%: {'beats it' if wins else 'does not beat it'}"
            )
            if wins:
                beaten.append(f"{name} by {recipe}")
    print("holds: nothing ships" if not beaten else f"does not hold: {', '.join(beaten)}")


if __name__ == "__main__":
    given = dict(arg.split("=", 1) for arg in sys.argv[1:])
    main({recipe: Path(folder) for recipe, folder in given.items()} if given else ROUNDS)
