"""Environment: task rewards, shaping, episode ends, auto-reset, action encodings, one compile per size."""

from __future__ import annotations

import chex
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from engine import SIZES
from kinetix_cli.actions import action_space, binding_values, engine_actions, sample_action
from kinetix_cli.env import EnvConfig, EnvParams, KinetixEnv, reset_from_pool, reset_to
from kinetix_cli.level import Bindings, stack_levels
from kinetix_cli.level_file import parse_level

CONFIG = EnvConfig(SIZES["s"])
ENV = KinetixEnv(CONFIG, reset_fn=None)  # levels are always passed explicitly here


def level(bodies, floor="neutral", joints=(), thrusters=()):
    data = {
        "format": "kinetix-level/1",
        "size": "s",
        "arena": {"floor": {"role": floor}},
        "bodies": bodies,
        "joints": list(joints),
        "thrusters": list(thrusters),
    }
    return parse_level(data).build()


def ball(name, x, y, role, r=0.2, **extra):
    return {"name": name, "shape": "circle", "radius": r, "position": [x, y], "role": role, **extra}


@pytest.fixture(scope="module")
def step_fn():
    """The compiled step without reset, shared by the tests (one trace for every level of size s)."""

    @jax.jit
    @chex.assert_max_traces(n=1)
    def step(state, action, params):
        return ENV.step_env(state, action, params)

    return step


def play(step_fn, lvl, steps, action=None, params=EnvParams()):
    """Step until done; returns (rewards, last info, steps taken)."""
    state = ENV.state_from_level(lvl)
    action = jnp.zeros(6, jnp.int32) if action is None else jnp.asarray(action)
    rewards = []
    for t in range(steps):
        state, reward, done, info = step_fn(state, action, params)
        rewards.append(float(reward))
        if bool(done):
            return rewards, info, t + 1
    return rewards, info, steps


def test_green_falling_on_blue_solves(step_fn):
    lvl = level([ball("g", 2.5, 1.2, "green"), ball("b", 2.5, 0.6, "blue", fixed=True)])
    rewards, info, steps = play(step_fn, lvl, 100, params=EnvParams(dense_reward_scale=0.0))
    assert bool(info["solved"]) and not bool(info["failed"])
    assert rewards[-1] == 1.0 and sum(rewards[:-1]) == 0.0
    assert 5 < steps < 40  # falls 0.4 m - 0.005 in about 0.29 s = 9 env steps


def test_red_floor_fails_and_takes_priority_over_blue(step_fn):
    lvl = level([ball("g", 1.0, 1.0, "green")], floor="red")
    _, info, _ = play(step_fn, lvl, 100)
    assert bool(info["failed"]) and not bool(info["solved"])
    # green rests on the red floor and touches the blue ball in the same step: -1 wins
    both = level([ball("g", 2.5, 0.6, "green"), ball("b", 2.8, 0.6, "blue", r=0.1, fixed=True)], floor="red")
    _, reward, done, info = step_fn(ENV.state_from_level(both), jnp.zeros(6, jnp.int32), EnvParams())
    assert bool(done) and bool(info["failed"]) and float(reward) == -1.0


def test_truncation_and_dense_shaping(step_fn):
    lvl = level([ball("g", 1.0, 0.61, "green"), ball("b", 4.0, 0.61, "blue")])
    params = EnvParams(max_steps=5, dense_reward_scale=0.5)
    rewards, info, steps = play(step_fn, lvl, 20, action=[0, 0, 0, 0, 0, 0], params=params)
    assert steps == 5 and bool(info["truncated"]) and not bool(info["solved"])
    np.testing.assert_allclose(float(info["distance"]), 3.0, atol=1e-3)
    np.testing.assert_allclose(sum(rewards), 0.0, atol=1e-4)  # resting bodies: no shaping


def test_shaping_rewards_approach(step_fn):
    thruster = {"body": "g", "direction_deg": 0, "power": 1.0, "binding": 1}
    lvl = level([ball("g", 1.0, 1.5, "green"), ball("b", 4.0, 1.5, "blue", fixed=True)], thrusters=[thruster])
    state = ENV.state_from_level(lvl)
    params = EnvParams(dense_reward_scale=0.1)
    new, reward, _, info = step_fn(state, jnp.array([0, 0, 0, 0, 0, 1]), params)
    expected = -(float(info["distance"]) - float(state.distance)) * 0.1
    np.testing.assert_allclose(float(reward), expected, rtol=1e-5)
    assert float(reward) > 0  # thruster binding 1 pushes green towards blue


def test_auto_reset_restarts_from_the_given_level(step_fn):
    lvl = level([ball("g", 2.5, 1.2, "green"), ball("b", 2.5, 0.6, "blue", fixed=True)])
    other = level([ball("g", 1.5, 2.0, "green"), ball("b", 3.5, 0.6, "blue", fixed=True)])
    state = ENV.state_from_level(lvl)
    step = jax.jit(ENV.step)
    for t in range(60):
        _, state, _, done, _ = step(jax.random.key(t), state, jnp.zeros(6, jnp.int32), EnvParams(), other)
        if bool(done):
            break
    assert bool(done) and int(state.steps) == 0
    np.testing.assert_allclose(state.physics.bodies.position[4:], other.physics.bodies.position[4:])


def test_non_finite_state_ends_the_episode(step_fn):
    lvl = level([ball("g", 2.5, 1.2, "green"), ball("b", 1.0, 0.6, "blue")])
    state = ENV.state_from_level(lvl)
    bodies = state.physics.bodies
    state = state.replace(
        physics=state.physics.replace(bodies=bodies.replace(velocity=bodies.velocity.at[4].set(jnp.nan)))
    )
    _, reward, done, info = step_fn(state, jnp.zeros(6, jnp.int32), EnvParams())
    assert bool(done) and float(reward) == 0.0 and not bool(info["solved"]) and not bool(info["truncated"])


def test_action_encodings():
    md = binding_values("multi-discrete", jnp.array([1, 2, 0, 1, 1, 0]))
    np.testing.assert_array_equal(md, [1, -1, 0, 1, 1, 0])
    expected = {0: [0] * 6, 1: [1, 0, 0, 0, 0, 0], 2: [-1, 0, 0, 0, 0, 0], 8: [0, 0, 0, -1, 0, 0], 9: [0] * 4 + [1, 0]}
    expected[10] = [0] * 5 + [1]
    for a, values in expected.items():
        np.testing.assert_array_equal(binding_values("discrete", jnp.int32(a)), values)
    cont = binding_values("continuous", jnp.array([2.0, -0.5, 0.0, 0.0, -1.0, 0.7]))
    np.testing.assert_allclose(cont, [1.0, -0.5, 0, 0, 0.0, 0.7])
    bindings = Bindings(jnp.array([3, 0]), jnp.array([False, True]), jnp.array([1, 0]))
    np.testing.assert_array_equal(
        engine_actions(bindings, jnp.array([0.5, -1, 0, 0.25, 0, 1.0])), [0.25, 1.0, 1.0, 0.0]
    )
    for kind in ("multi-discrete", "discrete", "continuous"):
        a = sample_action(kind, jax.random.key(0))
        assert a.shape == action_space(kind).shape


def test_vmapped_pool_reset_and_step():
    pool = stack_levels(
        [level([ball("g", 1.0 + i, 1.2, "green"), ball("b", 2.5, 0.6, "blue", fixed=True)]) for i in range(3)]
    )
    env = KinetixEnv(CONFIG, reset_from_pool(pool))
    keys = jax.random.split(jax.random.key(0), 8)
    obs, states = jax.vmap(env.reset, in_axes=(0, None))(keys, EnvParams())
    assert obs.shape == (8, 140)
    starts = set(np.round(np.asarray(states.physics.bodies.position[:, 5, 0]), 3))
    assert starts <= {1.0, 2.0, 3.0} and len(starts) > 1
    actions = jnp.zeros((8, 6), jnp.int32)
    obs, states, reward, done, info = jax.vmap(env.step, in_axes=(0, 0, 0, None))(keys, states, actions, EnvParams())
    assert obs.shape == (8, 140) and reward.shape == (8,) and info["solved"].shape == (8,)
    single = KinetixEnv(CONFIG, reset_to(jax.tree.map(lambda x: x[0], pool)))
    _, state = single.reset(jax.random.key(1), EnvParams())
    np.testing.assert_allclose(state.physics.bodies.position[5], [1.0, 1.2])
