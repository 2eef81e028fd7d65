"""Invariants over random scenes: no NaN, vmap equals single stepping, one compile per size, determinism."""

from __future__ import annotations

import hashlib

import chex
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from engine import SIZES, Params, Scene, Static, stack, step
from engine.random_scenes import random_actions, random_scene
from helpers.sim import simulate_batch


def _batch(static: Static, count: int, seed: int = 0):
    states = stack([random_scene(static, seed * 1000 + i).build_numpy(static) for i in range(count)])
    actions = jnp.asarray(random_actions(static, np.random.default_rng(seed), count))
    return states, actions


SLOW_M_L = ["s", pytest.param("m", marks=pytest.mark.slow), pytest.param("l", marks=pytest.mark.slow)]
"""Sizes: s in `make test`, m and l (more slots: compiles of 10-15 s each) in `make test-all`."""


@pytest.mark.slow  # every size (s: 15 s of make test's budget; the paper's levels step 256 random steps in it)
@pytest.mark.parametrize("size", ["s", "m", "l"])
def test_no_nan_over_1e5_random_steps(size):
    """128 random scenes x 840 steps (>= 10^5 scene-steps) per size: finite state, positions inside the clip box,
    speeds within the clip bounds."""
    static = SIZES[size]
    states, actions = _batch(static, 128, seed=1)
    states, parts = simulate_batch(static, states, 14, actions)
    for leaf in jax.tree.leaves(states):
        if jnp.issubdtype(leaf.dtype, jnp.floating):
            assert bool(jnp.isfinite(leaf).all())
    assert float(jnp.abs(states.bodies.position).max()) <= 15.0
    assert float(jnp.abs(states.bodies.velocity).max()) <= 100.0


@pytest.mark.slow
@pytest.mark.parametrize("size", ["s", "m", "l"])
def test_no_nan_over_1e5_consecutive_steps(size):
    """16 random scenes, each stepped 10^5 times in a row with fresh random actions every second."""
    static = SIZES[size]
    states, _ = _batch(static, 16, seed=2)
    rng = np.random.default_rng(3)
    for _ in range(100_000 // 60 + 1):
        actions = jnp.asarray(random_actions(static, rng, 16))
        states, _ = simulate_batch(static, states, 1, actions)
    assert all(bool(jnp.isfinite(x).all()) for x in jax.tree.leaves(states) if jnp.issubdtype(x.dtype, jnp.floating))


def test_vmap_equals_stepping_each_scene_alone():
    """Four different scenes stepped 60 times as a batch match stepping each alone (1e-5 m, 1e-4 m/s)."""
    static = SIZES["s"]
    states, actions = _batch(static, 4, seed=4)
    batched, _ = simulate_batch(static, states, 1, actions)
    single = jax.jit(lambda s, a: jax.lax.scan(lambda c, _: (step(static, Params(), c, a)[0], None), s, None, 60)[0])
    for i in range(4):
        alone = single(jax.tree.map(lambda x, i=i: x[i], states), actions[i])
        np.testing.assert_allclose(batched.bodies.position[i], alone.bodies.position, atol=1e-5)
        np.testing.assert_allclose(batched.bodies.velocity[i], alone.bodies.velocity, atol=1e-4)


def test_one_compile_per_size():
    """Different scenes (shapes, joints, roles, gravity) and different params of one size reuse one trace."""
    static = SIZES["s"]

    @jax.jit
    @chex.assert_max_traces(n=1)
    def advance(params, state, actions):
        return step(static, params, state, actions)[0]

    actions = jnp.zeros(static.num_actions)
    for seed in range(3):
        advance(Params(), random_scene(static, seed).build(static), actions)
    tiny = Scene(gravity=(0.0, -3.0))
    tiny.add_circle((1, 1), 0.1)
    advance(Params(dt=1 / 120), tiny.build(static), actions)


def test_dropped_contacts_are_reported():
    """With room for 2 contact points, a scene touching at more points reports the rest as dropped."""
    static = Static(num_polygons=6, num_circles=1, num_joints=0, num_thrusters=0, max_contacts=2)
    scene = Scene()
    scene.add_box((1.5, 0.6), (0.4, 0.4))
    scene.add_box((3.5, 0.6), (0.4, 0.4))
    scene.add_circle((2.5, 0.5), 0.1)
    state = scene.build(static)
    _, info = jax.jit(step, static_argnums=0)(static, Params(), state, jnp.zeros(0))
    assert int(info.dropped_contacts) == 3


def _fixed_scene(static):
    scene = Scene()
    a = scene.add_box((1.5, 1.2), (0.8, 0.3), angle=0.2)
    w = scene.add_circle((1.2, 0.9), 0.15)
    scene.add_circle((3.2, 2.0), 0.25, restitution=0.3)
    scene.add_revolute_joint(a, w, (1.2, 0.9), motor_speed=1.0)
    scene.add_thruster(a, (1.5, 1.2), angle=1.0)
    return scene.build(static)


def _run_fixed(static):
    run = jax.jit(lambda s, a: jax.lax.scan(lambda c, _: (step(static, Params(), c, a)[0], None), s, None, 120)[0])
    return run(_fixed_scene(static), jnp.array([0.7, 0.5]))


def test_determinism_bit_identical_and_hash():
    """Two runs are bit-identical; the state after 2 s, quantised to 1 mm / 1 mrad, matches a recorded hash
    (jax 0.10.2, CPU). A changed hash means the physics changed: re-record it deliberately."""
    static = SIZES["s"]
    first, second = _run_fixed(static), _run_fixed(static)
    for x, y in zip(jax.tree.leaves(first), jax.tree.leaves(second), strict=True):
        assert np.array_equal(np.asarray(x), np.asarray(y))
    b = first.bodies
    quantised = np.round(np.concatenate([np.asarray(b.position).ravel(), np.asarray(b.angle)]) * 1000).astype(np.int64)
    digest = hashlib.sha256(quantised.tobytes()).hexdigest()[:16]
    assert digest == GOLDEN_HASH, (digest, quantised.tolist())


GOLDEN_HASH = "f30f04767c67a917"
