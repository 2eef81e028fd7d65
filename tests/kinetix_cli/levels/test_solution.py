"""Solution records: run-length encoding, bad records, which bindings a level uses, and replays against the
no-op and random baselines."""

from __future__ import annotations

import numpy as np
import pytest

from helpers.levels import PUSH
from kinetix_cli.errors import LevelError
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.levels.solution import check_level, decode_solution, encode_solution, open_loop_actions, used_bindings


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


def test_check_level_replays_a_solution_and_the_baselines():
    spec = parse_level(PUSH)
    spec.solution = {"actions": [[[0, 0, 0, 0, 0, 1], 120]]}
    outcome = check_level(spec, attempts=3)
    assert bool(outcome["solution"].solved[0]) and not bool(outcome["noop"].solved[0])
    assert outcome["random"].solved.shape == (3,)
    np.testing.assert_array_equal(open_loop_actions(spec, "solution", 256)[:120, 5], 1)
