"""Rules 1 and 2 of PLAN.md, applied to the zero-shot validation records of this folder: per recipe and seed the
mean over all 180 validation levels and over each size's, each recipe's mean and standard deviation over its seeds,
and what each name ships. Run from the checkout's root: python docs/experiments/2026-11-28-agents-v4/decide.py
The second round applies the same rule to its own folder: decide.py docs/experiments/2026-11-29-agents-v4-round2 C D
and the third with general-m's shipped version replaced: decide.py FOLDER E F general-m=v3:ITS_ZERO_SHOT_RECORD;
the seventh with other training seeds: decide.py FOLDER K60 K120 seeds=20,21,22 general-m=v3:..."""

import json
import statistics
import sys
from pathlib import Path

FOLDER = Path(__file__).parent
RECIPES = ("A", "B")
SEEDS = (0, 1, 2)
PROTOCOL = FOLDER.parent / "2026-11-28-protocol"
SHIPPED = {"general": (None, "v3"), "general-s": ("s", "v2"), "general-m": ("m", "v2"), "general-l": ("l", "v2")}
"""Each name: the levels it is judged on (None: all 180), its shipped version (its record in the protocol study)."""
MARGIN = 0.01  # a recipe must lead by more than max(1.0 point, its seed sd)


def mean(record: dict, size: str | None) -> float:
    """Mean solve rate over the validation levels of `size` (held-out and ours, each level once), or all 180."""
    rates = [
        level["solve_rate"]
        for level in record["levels"]
        if size is None or level["suite"] in (f"levels/validation/{size}", f"levels/{size}")
    ]
    return sum(rates) / len(rates)


def main(
    folder: Path = FOLDER, recipes: tuple[str, ...] = RECIPES, replaced: dict | None = None, seeds: tuple = SEEDS
) -> None:
    """`replaced`: name -> (version, zero-shot record) of a shipped version newer than the protocol study's."""
    shipped_versions = {
        name: (size, version, PROTOCOL / f"zero-shot-{name}-{version}.json")
        for name, (size, version) in SHIPPED.items()
    }
    for name, (version, path) in (replaced or {}).items():
        shipped_versions[name] = (SHIPPED[name][0], version, Path(path))
    records = {(r, s): json.loads((folder / f"zero-shot-{r}-{s}.json").read_text()) for r in recipes for s in seeds}
    print("| recipe | seed | all 180 | s (50) | m (60) | l (70) |")
    print("|---|---|---|---|---|---|")
    for (recipe, seed), record in records.items():
        cells = " | ".join(f"{100 * mean(record, size):.1f}%" for size in (None, "s", "m", "l"))
        print(f"| {recipe} | {seed} | {cells} |")
    print()
    for name, (size, version, path) in shipped_versions.items():
        shipped = mean(json.loads(path.read_text()), size)
        stats = {}
        for recipe in recipes:
            scores = [mean(records[recipe, seed], size) for seed in seeds]
            stats[recipe] = (statistics.mean(scores), statistics.stdev(scores), scores)
        best = max(recipes, key=lambda r: stats[r][0])
        avg, sd, scores = stats[best]
        summary = "; ".join(f"{r} {100 * m:.2f}% (sd {100 * d:.2f})" for r, (m, d, _) in stats.items())
        if avg - shipped > max(MARGIN, sd):
            seed = seeds[scores.index(max(scores))]
            lead = 100 * (avg - shipped)
            verdict = (
                f"{best} beats the shipped {version} ({100 * shipped:.2f}%) by {lead:.2f} points: v4 = {best}-{seed}"
            )
        else:
            verdict = (
                f"no recipe beats the shipped {version} ({100 * shipped:.2f}%) by more than max(1.0, sd): it stays"
            )
        print(f"{name} ({size or 'all'}): {summary} -> {verdict}")


if __name__ == "__main__":
    if len(sys.argv) > 2:
        names = tuple(a for a in sys.argv[2:] if "=" not in a)
        replaced = dict(a.split("=", 1) for a in sys.argv[2:] if "=" in a)
        seeds = tuple(int(s) for s in replaced.pop("seeds", ",".join(map(str, SEEDS))).split(","))
        main(Path(sys.argv[1]), names, {n: tuple(v.split(":", 1)) for n, v in replaced.items()}, seeds)
    else:
        main()
