"""The CEM search finds a robust solution of an easy level, which then replays; a solved set keeps the search result
of every level of a set."""

from __future__ import annotations

import jax
import numpy as np
import pytest

from engine import SIZES
from helpers.cli import kinetix
from helpers.levels import PUSH
from helpers.levelsets import small_levelset
from kinetix_cli.env.episode import replay
from kinetix_cli.env.factory import make_env
from kinetix_cli.levels.levelset import load_levelset
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.levels.solution import SOLUTION_SETTINGS, check_level
from kinetix_cli.tools.solve import SolveConfig, solve, solve_levelset


def test_search_finds_a_robust_solution_that_replays():
    spec = parse_level(PUSH)
    result = solve(spec, SolveConfig(population=32, iterations=5, segments=8))
    assert result.solution is not None, "the easy level should be solved in a few iterations"
    assert all(entry[0][:5] == [0] * 5 for entry in result.solution["actions"])  # unused bindings stay off
    spec.solution = result.solution
    outcome = check_level(spec, attempts=4)
    assert bool(outcome["solution"].solved[0]) and int(outcome["solution"].length[0]) == result.length
    assert not bool(outcome["noop"].solved[0])
    assert outcome["random"].solved.shape == (4,)


@pytest.mark.slow  # ~28 s: a set solved and replayed; make test keeps the search and its replay (above)
def test_a_solved_set_keeps_each_levels_search_result_and_replays_its_solutions(capsys, tmp_path):
    """Six shipped s levels searched three at a time: every solution it stores solves its level, the unsolved are
    marked with no-op actions, the same command writes the same bytes, and `levels info` counts both."""
    small_levelset(tmp_path / "set")
    args = ["levels", "solve", tmp_path / "set", "--population", "16", "--iterations", "3", "--batch", "3"]
    assert kinetix(capsys, *args, "-o", tmp_path / "solved").code == 0
    solved = load_levelset(tmp_path / "solved")
    found = solved.solutions
    assert found.actions.shape == (6, 256, 6) and found.actions.dtype == np.int8
    assert found.solved.sum() >= 1 and solved.manifest["stats"]["solved"] == found.solved.sum()
    assert solved.manifest["settings"]["search"]["batch"] == 3
    assert not found.actions[~found.solved].any() and not found.length[~found.solved].any()
    env, params = make_env(SOLUTION_SETTINGS, SIZES["s"])
    outcome = replay(env, params, solved.levels, found.actions.astype(np.int32))
    np.testing.assert_array_equal(outcome.solved, found.solved)
    np.testing.assert_array_equal(outcome.length[found.solved], found.length[found.solved])
    assert kinetix(capsys, *args, "-o", tmp_path / "again").code == 0
    assert load_levelset(tmp_path / "again").manifest["shards"] == solved.manifest["shards"]  # same sha256s
    result = kinetix(capsys, "levels", "info", tmp_path / "solved")
    assert f"solutions: {found.solved.sum()} solved" in result.out
    line = kinetix(capsys, "levels", "solve", tmp_path / "solved" / "nowhere", "-o", tmp_path / "x").error_line
    assert "manifest.json: not found" in line


@pytest.mark.slow  # ~26 s: three solves of a set; make test keeps the search and its replay (above)
def test_a_solve_stopped_part_way_resumes_at_its_last_shard(capsys, tmp_path):
    """`--shard-size` sets how much a killed solve keeps: stopped after its first shard of 2 levels, the same command
    finishes the set, and it holds the same levels and search results as the source's layout (shards of 4)."""
    small_levelset(tmp_path / "set")
    config = SolveConfig(population=16, iterations=3)

    def stop(kept, stats):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        solve_levelset(tmp_path / "set", tmp_path / "solved", config, batch=3, progress=stop, shard_size=2)
    assert sorted(p.name for p in (tmp_path / "solved").iterdir()) == ["progress.json", "shard-00000.npz"]
    args = ["levels", "solve", tmp_path / "set", "--population", "16", "--iterations", "3", "--batch", "3"]
    assert kinetix(capsys, *args, "-o", tmp_path / "solved", "--shard-size", "2").code == 0
    assert kinetix(capsys, *args, "-o", tmp_path / "whole").code == 0
    resumed, whole = load_levelset(tmp_path / "solved"), load_levelset(tmp_path / "whole")
    assert [s["count"] for s in resumed.manifest["shards"]] == [2, 2, 2]
    assert [s["count"] for s in whole.manifest["shards"]] == [4, 2]
    for a, b in zip(jax.tree.leaves(resumed.levels), jax.tree.leaves(whole.levels), strict=True):
        np.testing.assert_array_equal(a, b)
    for field in ("actions", "solved", "length"):
        np.testing.assert_array_equal(getattr(resumed.solutions, field), getattr(whole.solutions, field))
