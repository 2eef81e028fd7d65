"""Solutions: run-length records, batched replay, and the CEM search on an easy level."""

from __future__ import annotations

import numpy as np
import pytest

from kinetix_cli.level_file import LevelError, parse_level
from kinetix_cli.solve import SolveConfig, check_level, decode_solution, encode_solution, solve, used_bindings

# A frictionless green box pushed by thruster binding 1 towards a blue ball 2 m to the right.
PUSH = {
    "format": "kinetix-level/1",
    "size": "s",
    "bodies": [
        {"name": "g", "shape": "box", "size": [0.3, 0.3], "position": [1.0, 0.55], "role": "green", "friction": 0},
        {"name": "b", "shape": "circle", "radius": 0.15, "position": [3.0, 0.55], "role": "blue", "fixed": True},
    ],
    "thrusters": [{"body": "g", "direction_deg": 0, "power": 0.5, "binding": 1}],
}


def test_encode_decode_round_trip():
    actions = np.zeros((10, 6), np.int32)
    actions[:3, 0] = 1
    actions[3:5, 5] = 1
    record = encode_solution(actions, 8)
    assert record == {"actions": [[[1, 0, 0, 0, 0, 0], 3], [[0, 0, 0, 0, 0, 1], 2]]}
    np.testing.assert_array_equal(decode_solution(record, "x", 10), actions)


@pytest.mark.parametrize(
    "record", [{}, {"actions": []}, {"actions": [[[3, 0, 0, 0, 0, 0], 1]]}, {"actions": [[[0, 0, 0, 0, 2, 0], 1]]}]
)
def test_bad_records_are_level_errors(record):
    with pytest.raises(LevelError, match="x.json: solution: actions"):
        decode_solution(record, "x.json", 256)


def test_used_bindings():
    level = parse_level(PUSH).build()
    np.testing.assert_array_equal(used_bindings(level), [False] * 5 + [True])


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
