"""Every shipped level in levels/{s,m,l}: it loads, its solution solves it, and doing nothing does not.

Levels of one size are replayed together in one batch (one compile per size).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from engine import SIZES
from helpers.paths import LEVELS
from kinetix_cli.env.episode import replay
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import stack_levels
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.solution import SOLUTION_SETTINGS, decode_solution

LEVELS = LEVELS
MINIMUM = {"s": 10, "m": 20, "l": 30}


def level_files(size: str) -> list[Path]:
    return sorted((LEVELS / size).glob("*.json"))


@pytest.mark.parametrize("size", ["s", "m", "l"])
def test_suite_is_complete_and_valid(size):
    files = level_files(size)
    assert len(files) >= MINIMUM[size], f"levels/{size} has {len(files)} levels, want >= {MINIMUM[size]}"
    for path in files:
        spec = load_level(path)
        assert spec.size == size, f"{path}: declares size {spec.size}"
        assert spec.description, f"{path}: needs a one-line description"
        assert spec.solution is not None, f"{path}: ships no solution"


@pytest.mark.parametrize(
    "size", ["s", pytest.param("m", marks=pytest.mark.slow), pytest.param("l", marks=pytest.mark.slow)]
)  # m and l: 12-14 s of compile each (make test-all)
def test_solutions_solve_and_noop_does_not(size):
    specs = [load_level(path) for path in level_files(size)]
    if not specs:
        pytest.skip(f"no levels in levels/{size}")
    static = SIZES[size]
    env, params = make_env(SOLUTION_SETTINGS, static)
    horizon = SOLUTION_SETTINGS.max_steps
    levels = [spec.build(static) for spec in specs]
    solutions = [decode_solution(spec.solution, spec.path, horizon) for spec in specs]
    batch = stack_levels(levels + levels)
    actions = np.stack(solutions + [np.zeros((horizon, 6), np.int32)] * len(specs))
    outcome = replay(env, params, batch, actions)
    n = len(specs)
    unsolved = [spec.path for spec, ok in zip(specs, outcome.solved[:n], strict=True) if not ok]
    self_solving = [spec.path for spec, ok in zip(specs, outcome.solved[n:], strict=True) if ok]
    assert not unsolved, f"solutions that do not solve their level: {unsolved}"
    assert not self_solving, f"levels a no-op policy solves: {self_solving}"


def test_readme_lists_every_level():
    readme = (LEVELS / "README.md").read_text()
    missing = [f"{size}/{path.name}" for size in MINIMUM for path in level_files(size)]
    missing = [name for name in missing if name not in readme]
    assert not missing, f"levels/README.md does not list {missing} (see its first lines to regenerate the table)"
