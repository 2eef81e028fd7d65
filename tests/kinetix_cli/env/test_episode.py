"""The episode runner: a recorded trace agrees with the outcome, and batched replays (padded to a power of two,
shared engine constants passed once) equal the same episodes played one by one."""

from __future__ import annotations

import jax
import numpy as np
import pytest

from engine import SIZES
from helpers.levels import FALL, PUSH
from kinetix_cli.config import EnvSettings
from kinetix_cli.env.episode import open_loop, replay, run_episode
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import stack_levels
from kinetix_cli.levels.parse import parse_level
from kinetix_cli.levels.solution import random_actions

SETTINGS = EnvSettings(size="s", observation="symbolic-flat")


def test_a_recorded_trace_matches_its_outcome():
    env, params = make_env(SETTINGS)
    level = parse_level(FALL).build()
    actions = np.zeros((64, 6), np.int32)
    play = jax.jit(lambda level: run_episode(env, params, level, open_loop(actions), jax.random.key(0), 64, True))
    outcome, trace = jax.device_get(play(level))
    length = int(outcome.length)
    assert bool(outcome.solved) and 0 < length < 64
    assert trace.done[length - 1] and trace.done.sum() == 1  # the step that ended it, once
    # [return]: < 64 float32 rewards of size <= 1 summed in another order
    np.testing.assert_allclose(trace.reward[:length].sum(), outcome.total_return, rtol=1e-6, atol=4e-6)
    assert trace.physics.bodies.position.shape == (64, SIZES["s"].num_bodies, 2)


@pytest.mark.slow  # 17 s; replays of one level are checked in make test (test_a_recorded_trace_matches_its_outcome)
def test_batched_replay_equals_one_by_one_with_mixed_engine_constants():
    env, params = make_env(SETTINGS)
    push, fall = parse_level(PUSH), FALL | {"params": {"dt": 0.025}}
    levels = [push.build(), parse_level(fall).build(), push.build()]
    actions = random_actions(3, 128, seed=1)
    together = replay(env, params, stack_levels(levels), actions)  # 3 rows padded to 4; dt differs: batched
    for i, level in enumerate(levels):
        alone = replay(env, params, stack_levels([level]), actions[i : i + 1])
        for name in ("solved", "failed", "length"):
            assert getattr(together, name)[i] == getattr(alone, name)[0], (i, name)
        np.testing.assert_allclose(together.total_return[i], alone.total_return[0], rtol=1e-5, atol=1e-6)
