"""Rule 1 of PLAN.md, applied to the zero-shot validation records of this folder: each candidate's mean over the
validation levels of a name's size (every level once), and the version each name ships (the best; within 1.0 point
of it, the newest). Run from the checkout's root: python docs/experiments/2026-11-28-protocol/decide.py"""

import json
from pathlib import Path

FOLDER = Path(__file__).parent
NAMES = {"general-s": "s", "general-m": "m", "general-l": "l", "general": None}
LEVEL = 0.01  # candidates within 1.0 point of the best count as level with it


def mean(record: dict, size: str | None) -> float:
    """Mean solve rate over the validation levels of `size` (held-out and ours), or all of them."""
    rates = [
        level["solve_rate"]
        for level in record["levels"]
        if size is None or level["suite"] in (f"levels/validation/{size}", f"levels/{size}")
    ]
    return sum(rates) / len(rates)


def main() -> None:
    for name, size in NAMES.items():
        scored = []
        for file in sorted(FOLDER.glob(f"zero-shot-{name}-v*.json")):
            version = int(file.stem.rsplit("-v", 1)[1])
            scored.append((version, mean(json.loads(file.read_text()), size)))
        best = max(score for _, score in scored)
        chosen = max(version for version, score in scored if score >= best - LEVEL)
        rows = ", ".join(f"v{version} {100 * score:.2f}%" for version, score in sorted(scored))
        print(f"{name} ({size or 'all'} validation levels): {rows} -> ships v{chosen}")


if __name__ == "__main__":
    main()
