"""Generation chunks: deterministic, counted, and the kept levels are not solved by doing nothing."""

from __future__ import annotations

import jax
import numpy as np
import pytest

from engine import SIZES
from kinetix_cli.env.episode import replay
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import level_count
from kinetix_cli.errors import UserError
from kinetix_cli.generator.filters import FILTER_SETTINGS, FilterConfig, generate_chunk, make_config, parse_filters

CHUNK = 32
pytestmark = pytest.mark.xdist_group("generate-s-32")  # with test_generate: one worker compiles the chunk program


@pytest.fixture(scope="session")
def chunk():
    config = make_config("s", CHUNK)
    return config, generate_chunk(config, seed=3, index=0)


def test_chunks_are_deterministic_and_counted(chunk):
    config, (levels, stats) = chunk
    again, _ = generate_chunk(config, seed=3, index=0)
    jax.tree.map(np.testing.assert_array_equal, levels, again)
    dropped = stats["dropped_invalid"] + stats["dropped_noop"] + stats["dropped_random"]
    assert stats["sampled"] == CHUNK and level_count(levels) + dropped == CHUNK and level_count(levels) > 0


def test_kept_levels_are_not_solved_by_doing_nothing(chunk):
    _, (levels, _) = chunk
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
