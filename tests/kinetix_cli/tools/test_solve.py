"""The CEM search finds a robust solution of an easy level, which then replays."""

from __future__ import annotations

from helpers.levels import PUSH
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.levels.solution import check_level
from kinetix_cli.tools.solve import SolveConfig, solve


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
