"""Generation chunks: counted, and the kept levels are not solved by doing nothing (that a chunk is the same
when made again: tests/kinetix_cli/cli/test_generate.py)."""

from __future__ import annotations

import numpy as np
import pytest

from engine import SIZES
from helpers.levelsets import CHUNK, GENERATE_GROUP
from kinetix_cli.env.episode import replay
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import level_count
from kinetix_cli.errors import UserError
from kinetix_cli.generator.filters import FILTER_SETTINGS, FilterConfig, parse_filters

pytestmark = GENERATE_GROUP


def test_chunks_are_counted(first_chunk):
    _, (levels, stats) = first_chunk
    dropped = stats["dropped_invalid"] + stats["dropped_noop"] + stats["dropped_random"]
    assert stats["sampled"] == CHUNK and level_count(levels) + dropped == CHUNK and level_count(levels) > 0


def test_kept_levels_are_not_solved_by_doing_nothing(first_chunk):
    _, (levels, _) = first_chunk
    env, params = make_env(FILTER_SETTINGS, SIZES["s"])
    noop = np.zeros((level_count(levels), FILTER_SETTINGS.max_steps, 6), np.int32)
    assert not replay(env, params, levels, noop).solved.any()


def test_filter_flags():
    assert parse_filters("noop,random") == (True, True)
    assert parse_filters("none") == (False, False)
    with pytest.raises(UserError, match="--filter"):
        parse_filters("noop,lucky")
    with pytest.raises(UserError, match="--random-max-rate"):
        FilterConfig(random_max_rate=2.0)
