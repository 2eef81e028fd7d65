"""The level sampler: every sampled level is a valid, well-formed task, and sampling is pure."""

from __future__ import annotations

import dataclasses
import functools

import chex
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import engine
from engine import NUM_ARENA_POLYGONS, SIZES, Params, rotate
from kinetix_cli.constants import BLUE, GREEN, RED
from kinetix_cli.generator.sampler import (
    SamplerConfig,
    compact_slots,
    default_config,
    is_valid,
    sample_level,
    size_recipe,
)

BATCH = 64


@functools.cache
def sampler(size: str):
    static = SIZES[size]
    return jax.jit(jax.vmap(functools.partial(sample_level, static, default_config(size))))


@functools.cache
def batch(size: str):
    keys = jax.random.split(jax.random.key(7), BATCH)
    return jax.device_get(sampler(size)(keys))


SIZES_UNDER_TEST = ["s", pytest.param("m", marks=pytest.mark.slow), pytest.param("l", marks=pytest.mark.slow)]
"""Size s in `make test` (each size's sampler takes 30-40 s to compile here); m and l in `make test-all`."""


@pytest.mark.parametrize("size", SIZES_UNDER_TEST)
def test_every_level_is_a_valid_task(size):
    static = SIZES[size]
    levels = batch(size)
    assert jax.jit(jax.vmap(functools.partial(is_valid, static)))(levels).all()
    bodies = levels.physics.bodies
    shapes = bodies.active.copy()
    shapes[:, :NUM_ARENA_POLYGONS] = False
    assert ((shapes & (bodies.role == GREEN)).sum(1) == 1).all()
    assert ((shapes & (bodies.role == BLUE)).sum(1) == 1).all()
    red = (shapes & (bodies.role == RED)).sum(1) + (bodies.role[:, 0] == RED)
    assert (red <= 1).all(), "at most one red entity (the floor counts)"
    pos = bodies.position[shapes]
    assert ((pos > 0) & (pos < 5)).all() and (pos[:, 1] > 0.4).all(), "shapes start inside the arena"
    assert not (shapes & ~np.isin(bodies.role, [0, 1, 2, 3])).any()
    if size == "s":
        assert not (shapes & bodies.fixed).any(), "nothing is fixed at size s"
    goal = shapes & np.isin(bodies.role, [GREEN, BLUE])
    assert (goal & ~bodies.fixed).any(1).all(), "green or blue can move"


@pytest.mark.parametrize("size", SIZES_UNDER_TEST)
def test_joints_and_thrusters_attach_to_active_bodies(size):
    levels = batch(size)
    physics, bindings = levels.physics, levels.bindings
    joints, thrusters, bodies = physics.joints, physics.thrusters, physics.bodies
    rows = np.arange(BATCH)[:, None]
    for body in (joints.body_a, joints.body_b):
        assert (bodies.active[rows, body] | ~joints.active).all()
    assert (bodies.active[rows, thrusters.body] & ~bodies.fixed[rows, thrusters.body] | ~thrusters.active).all()
    # both anchors of a joint are the same world point when the level starts (the shuffle kept them attached)
    world = lambda body, anchor: bodies.position[rows, body] + rotate(anchor, bodies.angle[rows, body], np)  # noqa: E731
    gap = np.linalg.norm(world(joints.body_a, joints.anchor_a) - world(joints.body_b, joints.anchor_b), axis=-1)
    assert (gap[joints.active] < 1e-4).all()
    assert ((bindings.motor >= 0) & (bindings.motor < 4)).all() and (
        (bindings.thruster >= 0) & (bindings.thruster < 2)
    ).all()


def test_sampling_is_pure_and_compiles_once():
    static = SIZES["s"]

    @jax.jit
    @chex.assert_max_traces(n=1)
    def one(key):
        return sample_level(static, default_config("s"), key)

    a, b, again = one(jax.random.key(1)), one(jax.random.key(2)), one(jax.random.key(1))
    chex.assert_trees_all_equal(a, again)
    assert not np.array_equal(a.physics.bodies.position, b.physics.bodies.position)


def test_a_size_mix_draws_each_listed_sizes_recipe():
    draw = jax.jit(jax.vmap(functools.partial(size_recipe, SIZES["m"], SamplerConfig(like=("s", "m")))))
    fill, thrusters, fixate = jax.device_get(draw(jax.random.split(jax.random.key(0), 400)))
    drawn = set(zip(fill.tolist(), thrusters.tolist(), fixate.tolist(), strict=True))
    assert drawn == {(0, 0, False), (2, 1, True)}, "like s: no fill, no extra thruster, nothing fixed; like m: m's"
    assert 0.4 < fixate.mean() < 0.6, "equal shares"
    own = size_recipe(SIZES["m"], default_config("m"), jax.random.key(0))
    assert tuple(map(int, own[:2])) == (2, 1) and bool(own[2])
    with pytest.raises(ValueError, match="like size 'l' do not fit"):
        size_recipe(SIZES["m"], SamplerConfig(like=("s", "l")), jax.random.key(0))


@pytest.mark.slow  # compiles the size-m sampler twice (~60 s)
def test_levels_like_s_in_m_slots_and_like_m_unchanged():
    keys = jax.random.split(jax.random.key(7), BATCH)
    static = SIZES["m"]
    draw_like_s = jax.jit(jax.vmap(functools.partial(sample_level, static, SamplerConfig(like=("s",)))))
    like_s = jax.device_get(draw_like_s(keys))
    bodies, thrusters = like_s.physics.bodies, like_s.physics.thrusters
    shapes = bodies.active[:, NUM_ARENA_POLYGONS:]
    assert (shapes.sum(1) <= 3).all(), "green, blue and at most a motor's shape: no fill tries"
    assert (thrusters.active.sum(1) <= 1).all() and not (shapes & bodies.fixed[:, NUM_ARENA_POLYGONS:]).any()
    assert jax.jit(jax.vmap(functools.partial(is_valid, static)))(like_s).all()
    like_m = jax.jit(
        jax.vmap(functools.partial(sample_level, static, dataclasses.replace(default_config("m"), like=("m",))))
    )
    # the same stream: a separately compiled program may round a float differently in its last bit
    chex.assert_trees_all_close(like_m(keys), batch("m"), rtol=1e-5, atol=1e-6)


@pytest.mark.slow  # a compile of ~25 s per size; `make test` steps generated scenes in test_filters and test_fresh
@pytest.mark.parametrize("size", ["s", "m", "l"])
def test_generated_scenes_simulate_without_nan(size):
    static = SIZES[size]
    levels = batch(size)
    step = jax.jit(jax.vmap(functools.partial(engine.step, static, Params())))
    physics = levels.physics
    actions = jnp.ones((BATCH, static.num_joints + static.num_thrusters))
    for _ in range(60):
        physics, _ = step(physics, actions)
    assert np.isfinite(np.asarray(physics.bodies.position)).all()


def test_compacting_slots_puts_active_ones_first_and_keeps_attachments(tiny_pool):
    """`compact_slots` (ACCEL's additions start from it) is a permutation: active bodies, joints and thrusters move to
    the front of their ranges, and every joint and thruster still holds the bodies it held."""
    static = SIZES["s"]
    level = jax.tree.map(lambda x: x[0], jax.device_get(tiny_pool))  # rocket-car-jump: a car (joint 0), a thruster
    wheel = int(level.physics.joints.body_b[0])  # take the wheel out: a gap before the last circle slot
    active = level.physics.bodies.active.copy()
    active[wheel] = False
    level = level.replace(physics=level.physics.replace(bodies=level.physics.bodies.replace(active=active)))
    compact = jax.device_get(jax.jit(compact_slots, static_argnums=0)(static, level))  # op by op: ~60 compiles

    def front_first(active):
        active = np.asarray(active)
        return (np.sort(active)[::-1] == active).all()

    assert not front_first(level.physics.bodies.active[static.num_polygons :])  # there was a gap
    active = compact.physics.bodies.active
    assert front_first(active[NUM_ARENA_POLYGONS : static.num_polygons]) and front_first(active[static.num_polygons :])

    def attachments(lv):
        b, j, t = lv.physics.bodies, lv.physics.joints, lv.physics.thrusters
        return sorted(
            [
                tuple(np.asarray(b.position[j.body_a[i]])) + tuple(np.asarray(b.position[j.body_b[i]]))
                for i in range(static.num_joints)
            ]
        ), sorted(
            [
                tuple(np.asarray(b.position[t.body[i]])) + tuple(np.asarray(t.anchor[i]))
                for i in range(static.num_thrusters)
            ]
        )

    assert attachments(compact) == attachments(level)
    assert int(active.sum()) == int(level.physics.bodies.active.sum())
