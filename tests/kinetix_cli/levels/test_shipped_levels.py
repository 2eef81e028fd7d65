"""Every shipped level in levels/{s,m,l}: it loads, its solution solves it, and doing nothing does not.

Levels of one size are replayed together in one batch (one compile per size), in a process compiled as `kinetix`
compiles.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from helpers.paths import LEVELS
from helpers.processes import TIMEOUT, release_env
from kinetix_cli.levels.files import load_level

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


REPLAY = """
import json, sys
from pathlib import Path
import numpy as np
from engine import SIZES
from kinetix_cli.env.episode import replay
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import stack_levels
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.solution import SOLUTION_SETTINGS, decode_solution

size, folder = sys.argv[1], Path(sys.argv[2])
specs = [load_level(path) for path in sorted(folder.glob("*.json"))]
static = SIZES[size]
env, params = make_env(SOLUTION_SETTINGS, static)
horizon = SOLUTION_SETTINGS.max_steps
levels = [spec.build(static) for spec in specs]
solutions = [decode_solution(spec.solution, spec.path, horizon) for spec in specs]
actions = np.stack(solutions + [np.zeros((horizon, 6), np.int32)] * len(specs))
solved = replay(env, params, stack_levels(levels + levels), actions).solved
n = len(specs)
print(json.dumps({
    "levels": n,
    "unsolved": [str(spec.path) for spec, ok in zip(specs, solved[:n]) if not ok],
    "self_solving": [str(spec.path) for spec, ok in zip(specs, solved[n:]) if ok],
}))
"""
"""Replays every level of one size with its solution and with no action, in one batch (one compile per size)."""


@pytest.mark.parametrize(
    "size", ["s", pytest.param("m", marks=pytest.mark.slow), pytest.param("l", marks=pytest.mark.slow)]
)  # m and l: 12-14 s of compile each (make test-all)
def test_solutions_solve_and_noop_does_not(size):
    """In a process compiled as `kinetix` compiles (`release_env`): under the suite's fast-compile settings
    levels/m/inchworm-crawl.json's recorded solution rounds its way to a miss, while users' replays solve it."""
    if not level_files(size):
        pytest.skip(f"no levels in levels/{size}")
    done = subprocess.run(
        [sys.executable, "-c", REPLAY, size, str(LEVELS / size)],
        env=release_env(),
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    result = json.loads(done.stdout.splitlines()[-1])
    assert result["levels"] == len(level_files(size))
    assert not result["unsolved"], f"solutions that do not solve their level: {result['unsolved']}"
    assert not result["self_solving"], f"levels a no-op policy solves: {result['self_solving']}"


def test_readme_lists_every_level():
    readme = (LEVELS / "README.md").read_text()
    missing = [f"{size}/{path.name}" for size in MINIMUM for path in level_files(size)]
    missing = [name for name in missing if name not in readme]
    assert not missing, f"levels/README.md does not list {missing} (see its first lines to regenerate the table)"
