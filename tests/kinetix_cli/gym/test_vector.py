"""The Gymnasium environments: Gymnasium's checker on the single environment, and the vector environment's numpy
batches, spaces, same-step auto-reset with the final observation kept, seeding and bad arguments."""

from __future__ import annotations

import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import kinetix_cli.gym  # noqa: F401  registers the id
from kinetix_cli.errors import UserError
from kinetix_cli.gym import ENV_ID, KinetixVectorEnv

INFINITE_BOUNDS = ("minimum value is -infinity", "maximum value is infinity")
"""The checker's only remarks: observation features (positions, velocities) have no bounds."""


def test_the_single_environment_passes_gymnasiums_checker():
    env = gymnasium.make(ENV_ID, levels="s", max_steps=8, observation="symbolic-entity")  # a Dict space
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped)
    remarks = [str(w.message) for w in caught]
    assert all(any(bound in remark for bound in INFINITE_BOUNDS) for remark in remarks), remarks
    obs, _ = env.reset(seed=3)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert isinstance(reward, float) and isinstance(terminated, bool) and set(info) == {"solved", "failed"}
    assert obs["polygons"].dtype == np.float32 and env.observation_space.contains(obs)


def test_the_vector_environment_keeps_terminated_truncated_and_the_final_observation():
    envs = gymnasium.make_vec(ENV_ID, num_envs=4, levels="s", max_steps=5)  # the random example's compile
    assert isinstance(envs.unwrapped, KinetixVectorEnv)
    assert envs.metadata["autoreset_mode"] == gymnasium.vector.AutoresetMode.SAME_STEP
    obs, _ = envs.reset(seed=7)
    again, _ = envs.reset(seed=7)
    np.testing.assert_array_equal(obs, again)  # a seed gives the same start
    assert envs.observation_space.contains(obs) and obs.shape == (4, 140) and obs.dtype == np.float32
    envs.action_space.seed(0)
    seen_end = False
    for _ in range(6):  # the 5-step cap ends every episode by the 5th step
        obs, reward, terminated, truncated, infos = envs.step(envs.action_space.sample())
        assert reward.dtype == np.float32 and reward.shape == (4,)
        assert terminated.dtype == truncated.dtype == np.bool_ and not (terminated & truncated).any()
        done = terminated | truncated
        np.testing.assert_array_equal(infos["_final_obs"], done)
        if done.any():
            seen_end = True
            assert not np.array_equal(infos["final_obs"][done], obs[done])  # obs is the new episode's start
            assert (infos["solved"][done] | infos["failed"][done] | truncated[done]).all()
        assert envs.observation_space.contains(obs)
    assert seen_end
    envs.close()


def test_bad_arguments_are_clear_errors():
    with pytest.raises(gymnasium.error.Error, match="num_envs"):
        KinetixVectorEnv(0, levels="s")
    with pytest.raises(UserError, match="observation: 'rgb'"):
        gymnasium.make_vec(ENV_ID, num_envs=2, observation="rgb")
    envs = KinetixVectorEnv(2, levels="s")
    with pytest.raises(gymnasium.error.ResetNeeded):
        envs.step(np.zeros((2, 6), np.int32))
