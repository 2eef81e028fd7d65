"""The validation suite's held-out levels as level sets, for `kinetix levels solve` (which reads sets, not files):
`tools.validation.heldout_levelset`, the generator call `kinetix validation build` exports from (the same seeds,
filters and count). Checks that each set's levels are the shipped files, then prints the folders. Run from the
checkout's root:
.venv/bin/python docs/experiments/2026-11-30-validation-signal/heldout_sets.py runs/validation-sets"""

import json
import sys
from pathlib import Path

from engine import SIZES
from kinetix_cli.levels.export import export_level
from kinetix_cli.levels.levelset import level_at, load_levelset
from kinetix_cli.levels.suites import SUITES
from kinetix_cli.tools.validation import HELDOUT_COUNT, heldout_levelset


def main(root: Path) -> None:
    for size in SUITES:
        where = root / size
        if not where.exists():
            heldout_levelset(where, size)
        levelset = load_levelset(where)
        for index in range(HELDOUT_COUNT):
            made = export_level(level_at(levelset, index), SIZES[size], name="x", description="x")
            shipped = json.loads(Path(f"levels/validation/{size}/validation-{size}-{index:03d}.json").read_text())
            same = {k: v for k, v in made.items() if k not in ("name", "description")} == {
                k: v for k, v in shipped.items() if k not in ("name", "description")
            }
            assert same, f"{where} level {index} is not levels/validation/{size}/validation-{size}-{index:03d}.json"
        print(where, f"{HELDOUT_COUNT} levels, the shipped files")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
