"""Environment: task rewards, shaping, episode ends (terminated and truncated apart), auto-reset with the final
observation, per-level engine constants, action encodings, one compile per size."""

from __future__ import annotations

import chex
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from engine import SIZES
from kinetix_cli.env.actions import action_space, binding_values, engine_actions, sample_action
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.level import Bindings, draw_level, index_level, stack_levels
from kinetix_cli.levels.parse import parse_level

ENV = KinetixEnv(SIZES["s"])


def level(bodies, floor="neutral", joints=(), thrusters=(), params=None):
    data = {
        "format": "kinetix-level/1",
        "size": "s",
        "arena": {"floor": {"role": floor}},
        "bodies": bodies,
        "joints": list(joints),
        "thrusters": list(thrusters),
        "params": params or {},
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
        _, state, reward, terminated, truncated, info = ENV.step_env(state, action, params)
        return state, reward, terminated | truncated, info | {"terminated": terminated, "truncated": truncated}

    return step


def play(step_fn, lvl, steps, action=None, params=EnvParams()):
    """Step until done; returns (rewards, last info, steps taken)."""
    state = ENV.initial_state(lvl)
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
    _, reward, done, info = step_fn(ENV.initial_state(both), jnp.zeros(6, jnp.int32), EnvParams())
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
    state = ENV.initial_state(lvl)
    params = EnvParams(dense_reward_scale=0.1)
    new, reward, _, info = step_fn(state, jnp.array([0, 0, 0, 0, 0, 1]), params)
    expected = -(float(info["distance"]) - float(state.distance)) * 0.1
    # [reward]: 0.1 x the difference of two ~3 m distances, each within a few float32 ulps (2.4e-7 m) of the other's
    np.testing.assert_allclose(float(reward), expected, rtol=1e-5, atol=1e-7)
    assert float(reward) > 0  # thruster binding 1 pushes green towards blue


def test_auto_reset_restarts_from_the_given_level_and_keeps_the_final_observation():
    lvl = level([ball("g", 2.5, 1.2, "green"), ball("b", 2.5, 0.6, "blue", fixed=True)])
    other = level([ball("g", 1.5, 2.0, "green"), ball("b", 3.5, 0.6, "blue", fixed=True)])
    state = ENV.initial_state(lvl)
    step = jax.jit(ENV.step)
    for _ in range(60):
        before = state
        obs, state, reward, terminated, truncated, info = step(state, jnp.zeros(6, jnp.int32), EnvParams(), other)
        if bool(terminated | truncated):
            break
    assert bool(terminated) and not bool(truncated) and float(reward) > 0.5
    assert int(state.steps) == 0
    np.testing.assert_allclose(state.physics.bodies.position[4:], other.physics.bodies.position[4:], atol=1e-6)  # [m]
    np.testing.assert_array_equal(obs, jax.jit(ENV.reset_to_level)(other)[0])  # the observation of the new episode
    final_obs, *_ = jax.jit(ENV.step_env)(before, jnp.zeros(6, jnp.int32), EnvParams())
    np.testing.assert_array_equal(info["final_observation"], final_obs)  # and the one before the reset
    assert not np.array_equal(info["final_observation"], obs)


def test_truncation_is_reported_apart_from_termination(step_fn):
    lvl = level([ball("g", 1.0, 0.61, "green"), ball("b", 4.0, 0.61, "blue")])
    state = ENV.initial_state(lvl)
    params = EnvParams(max_steps=3)
    ends = []
    for _ in range(3):
        state, _, done, info = step_fn(state, jnp.zeros(6, jnp.int32), params)
        ends.append((bool(done), bool(info["terminated"]), bool(info["truncated"])))
    assert ends == [(False, False, False), (False, False, False), (True, False, True)]


def test_a_levels_engine_constants_are_used(step_fn):
    """A level file's `params` ride in the level and the environment steps with them (here: the same ball
    falls farther per step with a doubled time step)."""
    bodies = [ball("g", 2.5, 3.0, "green"), ball("b", 1.0, 0.6, "blue", fixed=True)]
    normal, slow = level(bodies), level(bodies, params={"dt": 2.0 / 60.0})
    assert float(slow.engine_params.dt) == np.float32(2 / 60) and float(normal.engine_params.dt) == np.float32(1 / 60)
    drop = {}
    for name, lvl in (("normal", normal), ("slow", slow)):
        state = ENV.initial_state(lvl)
        state, *_ = step_fn(state, jnp.zeros(6, jnp.int32), EnvParams())
        drop[name] = 3.0 - float(state.physics.bodies.position[5, 1])
    # symplectic Euler from rest: two engine steps drop the ball by g dt^2 (1 + 2), so doubling dt drops it 4x
    # [m]: 1e-3 of an 8 mm drop; a float32 height of 3 m carries 2.4e-7 m
    assert drop["normal"] == pytest.approx(9.81 * 3 / 60**2, rel=1e-3, abs=1e-6)
    assert drop["slow"] == pytest.approx(4 * drop["normal"], rel=1e-3, abs=1e-6)


def test_non_finite_state_ends_the_episode(step_fn):
    lvl = level([ball("g", 2.5, 1.2, "green"), ball("b", 1.0, 0.6, "blue")])
    state = ENV.initial_state(lvl)
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
    np.testing.assert_allclose(cont, [1.0, -0.5, 0, 0, 0.0, 0.7], atol=1e-7)  # [binding value, -1..1]
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
    keys = jax.random.split(jax.random.key(0), 8)
    levels = jax.jit(jax.vmap(draw_level, in_axes=(None, 0)))(pool, keys)
    obs, states = jax.jit(jax.vmap(ENV.reset_to_level))(levels)
    assert obs.shape == (8, 140)
    starts = set(np.round(np.asarray(states.physics.bodies.position[:, 5, 0]), 3))
    assert starts <= {1.0, 2.0, 3.0} and len(starts) > 1
    actions = jnp.zeros((8, 6), jnp.int32)
    step = jax.jit(jax.vmap(ENV.step, in_axes=(0, 0, None, 0)))
    obs, states, reward, terminated, truncated, info = step(states, actions, EnvParams(), levels)
    assert obs.shape == (8, 140) and reward.shape == (8,) and info["solved"].shape == (8,)
    assert terminated.shape == truncated.shape == (8,) and info["final_observation"].shape == (8, 140)
    state = ENV.initial_state(index_level(pool, 0))
    np.testing.assert_allclose(state.physics.bodies.position[5], [1.0, 1.2], atol=1e-6)  # [m]
