"""The gymnax environment: step for step what `KinetixEnv` does from the same state, its spaces, its level
sources, one compile for another pool of the same size, and one clear error per bad setting."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from gymnax.environments.environment import Environment

from helpers.paths import REPO
from kinetix_cli.env.level import index_level
from kinetix_cli.errors import LevelError, UserError
from kinetix_cli.gym import make
from kinetix_cli.gym.environment import _step

STEPS = 40
CLOSE = {"rtol": 1e-5, "atol": 1e-6}


@pytest.fixture(scope="module")
def suite_s():
    """The shipped s suite as a pool (10 levels), episodes cut at 12 steps so that some end in the test."""
    return make("s", max_steps=12)


def test_each_step_is_kinetix_envs_step_and_ended_episodes_restart_from_the_pool(suite_s):
    env, params = suite_s
    assert isinstance(env, Environment) and env.name == "Kinetix-s"
    starts = [env.env.reset_to_level(index_level(params.pool, i))[0] for i in range(int(params.pool_count))]
    obs, state = env.reset(jax.random.key(0), params)
    assert any(np.array_equal(obs, start) for start in starts)
    space = env.action_space(params)
    step_env = jax.jit(env.env.step_env)  # two programs: floats agree to rounding (CLOSE), flags exactly
    ended = 0
    for t in range(STEPS):
        key, action_key = jax.random.split(jax.random.key(t))
        action = space.sample(action_key)
        want_obs, want_state, want_reward, want_term, want_trunc, want_info = step_env(state, action, params.env_params)
        obs, state, reward, terminated, truncated, info = env.step(key, state, action, params)
        assert float(reward) == pytest.approx(float(want_reward), abs=1e-6)
        assert bool(terminated) == bool(want_term) and bool(truncated) == bool(want_trunc)
        np.testing.assert_allclose(info["final_observation"], want_obs, **CLOSE)
        assert bool(info["solved"]) == bool(want_info["solved"])
        if want_term or want_trunc:
            ended += 1
            assert int(state.steps) == 0 and any(np.array_equal(obs, start) for start in starts)
        else:
            np.testing.assert_allclose(obs, want_obs, **CLOSE)
            assert int(state.steps) == int(want_state.steps)
        assert bool(env.observation_space(params).contains(obs))
    assert ended >= 2  # 40 steps with a 12-step cap


def test_another_pool_of_the_same_size_and_bucket_does_not_compile_again(suite_s):
    env, params = suite_s
    other_env, other = make(REPO / "levels" / "s" / "pad-to-pad.json", size="s", max_steps=12)
    other = other.replace(pool=jax.tree.map(lambda x: jnp.concatenate([x] * 16)[:16], other.pool))  # 16 rows
    assert other_env == env and int(other.pool_count) == 1
    state = env.reset(jax.random.key(1), params)[1]
    action = jnp.zeros(6, jnp.int32)
    env.step(jax.random.key(2), state, action, params)
    compiled = _step._cache_size()
    _, state, *_ = env.step(jax.random.key(3), state, action, other)
    assert _step._cache_size() == compiled


@pytest.mark.slow  # the generator's compile (~40 s); entity observations are in make test through test_vector
def test_fresh_levels_and_entity_observations():
    env, params = make("fresh", size="s", observation="symbolic-entity", action="discrete", max_steps=4)
    assert params.pool is None and env.num_actions == 11
    obs, state = env.reset(jax.random.key(0), params)
    space = env.observation_space(params)
    assert bool(space.contains(obs)) and space.spaces["polygons"].shape == obs.polygons.shape
    for t in range(5):  # the 4th step truncates, and a new fresh level starts
        obs, state, _, terminated, truncated, _ = env.step(jax.random.key(t), state, jnp.int32(t % 11), params)
    assert int(state.steps) <= 1


def test_bad_settings_are_one_clear_error(tmp_path):
    for kwargs, message in [
        ({"observation": "rgb"}, "observation: 'rgb' is not one of"),
        ({"action": "joystick"}, "action: 'joystick' is not one of"),
        ({"size": "xl"}, "size: 'xl' is not one of"),
        ({"levels": []}, "levels: an empty list"),
        ({"levels": "no/such/folder"}, "no/such/folder: no such file or folder"),
        ({"levels": "l", "size": "s"}, "but the size holds"),
    ]:
        with pytest.raises(UserError, match=message):
            make(**kwargs)
    (tmp_path / "bad.json").write_text('{"format": "kinetix-level/1", "bodies": 3}')
    with pytest.raises(LevelError, match="bad.json"):
        make(tmp_path / "bad.json")
