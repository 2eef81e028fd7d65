"""Every shipped level in levels/{s,m,l}: it loads, its solution solves it, and doing nothing does not.

Levels of one size are replayed together by `kinetix validate --play`, in a process compiled as `kinetix` compiles.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from helpers.paths import LEVELS
from helpers.processes import KINETIX, TIMEOUT, release_env
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


@pytest.mark.parametrize(
    "size", ["s", pytest.param("m", marks=pytest.mark.slow), pytest.param("l", marks=pytest.mark.slow)]
)  # m and l: 12-14 s of compile each (make test-all)
def test_solutions_solve_and_noop_does_not(size):
    """`kinetix validate --play` (each solution, a no-op and 20 random policies, one batch per size) in a process
    compiled as `kinetix` compiles (`release_env`): under the suite's fast-compile settings
    levels/m/inchworm-crawl.json's recorded solution rounds its way to a miss, while users' replays solve it."""
    files = level_files(size)
    if not files:
        pytest.skip(f"no levels in levels/{size}")
    done = subprocess.run(
        [*KINETIX, "validate", "--play", str(LEVELS / size)],
        env=release_env(),
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    report = done.stdout + done.stderr
    failing = [line for line in report.splitlines() if "solution does not solve" in line or "no-op solves" in line]
    assert done.returncode == 0 and not failing, report[-3000:]
    assert f"{len(files)} level file(s) valid" in report


def test_readme_lists_every_level():
    readme = (LEVELS / "README.md").read_text()
    missing = [f"{size}/{path.name}" for size in MINIMUM for path in level_files(size)]
    missing = [name for name in missing if name not in readme]
    assert not missing, f"levels/README.md does not list {missing} (see its first lines to regenerate the table)"
