"""PLAN.md's rule 4 after seed 20's four copies: does any copy score above a shipped version on that version's
levels? Run from the checkout's root: python docs/experiments/2026-11-30-agents-v4-round7/stop.py"""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[1] / "2026-11-28-agents-v4"))
from decide import PROTOCOL, SHIPPED, mean  # noqa: E402  (the study scripts are not a package)

FOLDER = Path(__file__).parent
RECORDS = {name: PROTOCOL / f"zero-shot-{name}-{version}.json" for name, (_, version) in SHIPPED.items()}
RECORDS["general-m"] = FOLDER.parent / "2026-11-29-agents-v4-round2" / "zero-shot-D-2.json"  # general-m v3


def main(seed: int = 20) -> None:
    records = {t: json.loads((FOLDER / f"zero-shot-K{t}-{seed}.json").read_text()) for t in (60, 120, 180, 240)}
    above = []
    for name, (size, _) in SHIPPED.items():
        shipped = mean(json.loads(RECORDS[name].read_text()), size)
        scores = {t: mean(record, size) for t, record in records.items()}
        cells = ", ".join(f"K{t} {100 * s:.2f}%" for t, s in scores.items())
        wins = [t for t, s in scores.items() if s > shipped]
        above += [f"{name} at K{t}" for t in wins]
        print(f"{name} ({size or 'all'}, shipped {100 * shipped:.2f}%): {cells}")
    verdict = (
        f"above a shipped version: {', '.join(above)}; seeds 21 and 22 follow"
        if above
        else ("no copy above a shipped version: the round stops at one seed (rule 4)")
    )
    print(verdict)


if __name__ == "__main__":
    main()
