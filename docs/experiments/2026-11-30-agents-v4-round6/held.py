"""RERUN.md's test: the fourth round's re-run test (its held.py) with recipe I, seeds 0-2 from this folder and seed 3
from the fresh clone (`rerun-zero-shot-I-3.json`). Run from the checkout's root:
python docs/experiments/2026-11-30-agents-v4-round6/held.py"""

import importlib.util
from pathlib import Path

HERE = Path(__file__).parent
_spec = importlib.util.spec_from_file_location("held", HERE.parent / "2026-11-29-agents-v4-round4" / "held.py")
held = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(held)

if __name__ == "__main__":
    held.ROUNDS = {"I": HERE}
    held.main()
