"""The gymnax environment: step for step what `KinetixEnv` does from the same state, gymnax 1.x's info keys, its
spaces and gymnax's wrappers on them, its level sources (fresh levels ride in params as a pool: a step samples
nothing, a new batch compiles nothing), one compile for another pool of the same size, and one clear error per bad
setting."""

from __future__ import annotations

import gymnasium
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from gymnax.environments.environment import Environment
from gymnax.wrappers.compat import LegacyStepAPIWrapper
from gymnax.wrappers.gym import GymnaxToGymWrapper
from gymnax.wrappers.purerl import LogWrapper, StickyActionWrapper

from helpers.paths import REPO
from helpers.traces import traces
from kinetix_cli.env.level import index_level, level_count
from kinetix_cli.errors import LevelError, UserError
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.gym import KinetixGymnax, make

STEPS = 40
CLOSE = {"rtol": 1e-5, "atol": 1e-6}


@pytest.fixture(scope="module")
def suite_s():
    """The shipped s suite as a pool (10 levels), episodes cut at 12 steps so that some end in the test."""
    return make("s", max_steps=12)


@pytest.fixture(scope="module")
def fresh_s():
    """Fresh levels at s in batches of 4 (the sampler's compile: the vector environment's tests share it)."""
    return make("fresh", size="s", fresh_levels=4, max_steps=12)


def test_each_step_is_kinetix_envs_step_and_ended_episodes_restart_from_the_pool(suite_s):
    env, params = suite_s
    assert isinstance(env, Environment) and env.name == "Kinetix-s"
    starts = [env.env.reset_to_level(index_level(params.pool, i))[0] for i in range(int(params.pool_count))]

    def a_start(obs) -> bool:  # another program computed it: equal up to float32 rounding (CLOSE)
        return any(np.allclose(obs, start, **CLOSE) for start in starts)

    obs, state = env.reset(jax.random.key(0), params)
    assert a_start(obs)
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
            assert int(state.steps) == 0 and a_start(obs)
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
    with traces() as traced:
        _, state, *_ = env.step(jax.random.key(3), state, action, other)
    assert traced[0] == 0


def test_info_carries_gymnax_terminated_truncated_and_discount(suite_s):
    env, params = suite_s
    _, state = env.reset(jax.random.key(0), params)
    for t in range(13):  # the 12-step cap truncates an episode that has not terminated
        _, state, _, terminated, truncated, info = env.step(jax.random.key(t), state, jnp.zeros(6, jnp.int32), params)
        assert bool(info["terminated"]) == bool(terminated) and bool(info["truncated"]) == bool(truncated)
        assert info["discount"].dtype == jnp.float32 and float(info["discount"]) == 1.0 - float(terminated)
        assert {"final_observation", "solved", "failed"} <= set(info)


def test_a_fresh_step_samples_nothing_it_is_the_pool_step(suite_s):
    env, params = suite_s
    fresh = KinetixGymnax(env.env, FreshLevels.for_size(env.env.static, "s"), params)
    state = env.reset(jax.random.key(0), params)[1]

    def program(gymnax_env):
        return str(jax.make_jaxpr(gymnax_env.step)(jax.random.key(1), state, jnp.zeros(6, jnp.int32), params))

    assert program(fresh) == program(env)


def test_fresh_levels_ride_in_params_and_a_new_batch_compiles_nothing(fresh_s):
    env, params = fresh_s
    assert env.fresh is not None and level_count(params.pool) == 4 and int(params.pool_count) == 4
    _, state = env.reset(jax.random.key(0), params)
    action = jnp.zeros(6, jnp.int32)
    env.step(jax.random.key(1), state, action, params)
    env.refresh_levels(jax.random.key(5), params)  # the sampler's batch, compiled once
    with traces() as traced:
        refreshed = env.refresh_levels(jax.random.key(2), params)
        assert not _same(refreshed.pool, params.pool) and int(refreshed.pool_count) == 4
        env.step(jax.random.key(1), state, action, refreshed)
    assert traced[0] == 0
    shaped = jax.eval_shape(env.refresh_levels, jax.random.key(2), params)  # jittable: it traces
    shapes = [jax.tree.map(lambda x: (x.shape, x.dtype), (p.pool, p.pool_count)) for p in (shaped, params)]
    assert shapes[0] == shapes[1]
    suite_env, suite = make("s")
    assert suite_env.refresh_levels(jax.random.key(3), suite) is suite  # a loaded pool has no sampler


def test_gymnax_wrappers_take_the_documented_action_spaces(suite_s):
    env, params = suite_s
    key, action = jax.random.key(0), jnp.zeros(6, jnp.int32)
    gym_env = GymnaxToGymWrapper(env, params)  # the default multi-discrete space: a gymnax Box of integers
    space = gym_env.action_space
    assert isinstance(space, gymnasium.spaces.Box) and space.dtype == np.int32
    np.testing.assert_array_equal(space.high, [2, 2, 2, 2, 1, 1])
    gym_env.reset(seed=0)
    assert len(gym_env.step(space.sample())) == 5
    state = env.reset(key, params)[1]
    legacy = LegacyStepAPIWrapper(env)  # the five-value step of gymnax < 1.0: done = terminated | truncated
    obs, _, reward, done, info = jax.eval_shape(legacy.step, key, state, action, params)
    assert done.dtype == jnp.bool_ and {"terminated", "truncated", "discount", "final_observation"} <= set(info)
    logged = LogWrapper(env)
    info = jax.eval_shape(logged.step, key, jax.eval_shape(logged.reset, key, params)[1], action, params)[5]
    assert "returned_episode_returns" in info and "terminated" in info
    discrete_env, discrete = make("s", action="discrete")
    sticky = StickyActionWrapper(discrete_env, 0.25)  # it takes a Discrete space only: action="discrete"
    sticky_state = jax.eval_shape(sticky.reset, key, discrete)[1]
    assert jax.eval_shape(sticky.step, key, sticky_state, jnp.int32(3), discrete)[2].shape == ()
    assert discrete_env.num_actions == 11 and env.num_actions == 6
    with pytest.raises(ValueError, match="Discrete"):
        StickyActionWrapper(env, 0.25)


@pytest.mark.slow  # the generator's compile (~40 s); entity observations are in make test through test_vector
def test_fresh_levels_and_entity_observations():
    env, params = make("fresh", size="s", observation="symbolic-entity", action="discrete", max_steps=4, fresh_levels=4)
    assert level_count(params.pool) == 4 and env.num_actions == 11
    obs, state = env.reset(jax.random.key(0), params)
    space = env.observation_space(params)
    assert bool(space.contains(obs)) and space.spaces["polygons"].shape == obs.polygons.shape
    for t in range(5):  # the 4th step truncates, and a new fresh level starts
        obs, state, _, terminated, truncated, _ = env.step(jax.random.key(t), state, jnp.int32(t % 11), params)
    assert int(state.steps) <= 1


def _same(a, b) -> bool:
    return jax.tree.all(jax.tree.map(np.array_equal, a, b))


def test_bad_settings_are_one_clear_error(tmp_path):
    for kwargs, message in [
        ({"observation": "rgb"}, "^observation: expected one of .*got 'rgb'"),  # an experiment config's words
        ({"action": "joystick"}, "^action: expected one of .*got 'joystick'"),
        ({"size": "xl"}, "^size: expected one of .*got 'xl'"),
        ({"frame_skip": 0}, "^frame_skip: must be >= 1"),
        ({"levels": []}, "levels: an empty list"),
        ({"levels": "no/such/folder"}, "no/such/folder: no such file or folder"),
        ({"levels": "l", "size": "s"}, "but the size holds"),
        ({"levels": "s", "fresh_levels": 4}, "fresh_levels: only for levels='fresh'"),
        ({"levels": "fresh", "fresh_levels": 0}, "fresh_levels: expected a whole number >= 1"),
    ]:
        with pytest.raises(UserError, match=message):
            make(**kwargs)
    (tmp_path / "bad.json").write_text('{"format": "kinetix-level/1", "bodies": 3}')
    with pytest.raises(LevelError, match="bad.json"):
        make(tmp_path / "bad.json")
