"""Folders of the repository the tests read."""

from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
LEVELS = REPO / "levels"
"""The hand-made levels: levels/{s,m,l}/*.json."""
EXPERIMENTS = REPO / "experiments"
REFERENCE_LEVELS = REPO / ".cache" / "reference-levels"
"""The reference's 74 levels (`make reference-levels`; `make test` fetches them)."""
