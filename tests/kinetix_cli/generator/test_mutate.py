"""ACCEL's edits: mutations of valid levels stay valid, keep every joint closed and the arena in place, keep the
roles a level has, and change most levels; each edit kind does what it says."""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from engine import NUM_ARENA_POLYGONS, rotate
from helpers.runs import tiny_config
from kinetix_cli.constants import BLUE, GREEN
from kinetix_cli.env.factory import make_env
from kinetix_cli.generator import mutate
from kinetix_cli.generator.sampler import is_valid

COPIES = 24


@pytest.fixture(scope="module")
def levels(tiny_pool):
    """The tiny run's two hand-made levels, COPIES of each, and their size."""
    static = make_env(tiny_config().env)[0].static
    return static, jax.tree.map(lambda x: jnp.repeat(x, COPIES, axis=0), tiny_pool)


def joint_gaps(level) -> jax.Array:
    """(J,) distance between the two world anchors of each active joint [m] (0 for inactive joints)."""
    b, j = level.physics.bodies, level.physics.joints
    world = lambda body, anchor: b.position[body] + jax.vmap(rotate)(anchor, b.angle[body])  # noqa: E731
    gap = jnp.linalg.norm(world(j.body_a, j.anchor_a) - world(j.body_b, j.anchor_b), axis=-1)
    return jnp.where(j.active, gap, 0.0)


def joints(level) -> int:
    return int(level.physics.joints.active.sum())


@pytest.mark.slow  # 30 s; each edit's own effect is checked in make test (test_each_edit_changes_what_it_names)
def test_mutations_stay_valid_closed_and_in_the_arena(levels):
    static, batch = levels
    mutated = jax.jit(jax.vmap(functools.partial(mutate.mutate_level, static, edits=5)))(
        jax.random.split(jax.random.key(0), 2 * COPIES), batch
    )
    valid = jax.jit(jax.vmap(functools.partial(is_valid, static)))
    was_valid = np.asarray(valid(batch))
    assert was_valid[:COPIES].all(), "rocket-car-jump is a valid level"
    assert np.asarray(valid(mutated))[was_valid].all()  # (pad-to-pad rests shapes on each other: no edit is kept)
    before, after = jax.vmap(joint_gaps)(batch), jax.vmap(joint_gaps)(mutated)  # slots are shuffled: compare the worst
    assert (after.max(axis=1) <= before.max(axis=1) + 1e-4).all()  # added joints are closed too
    arena = slice(0, NUM_ARENA_POLYGONS)
    np.testing.assert_array_equal(mutated.physics.bodies.position[:, arena], batch.physics.bodies.position[:, arena])
    count = lambda lv, role: np.sum(lv.physics.bodies.active & (lv.physics.bodies.role == role), axis=1)  # noqa: E731
    for role in (GREEN, BLUE):  # added shapes are neutral or red; a swap exchanges two roles
        np.testing.assert_array_equal(count(mutated, role), count(batch, role))
    pairs = list(zip(jax.tree.leaves(mutated), jax.tree.leaves(batch), strict=True))
    changed = np.array([not all(np.array_equal(a[i], b[i]) for a, b in pairs) for i in range(2 * COPIES)])
    assert changed[was_valid].mean() > 0.8 and not changed[~was_valid].any(), changed


first_level = jax.jit(lambda batch: jax.tree.map(lambda x: x[0], batch))  # op by op: ~50 small compiles


@pytest.mark.parametrize("edit", mutate._EDIT_FUNCTIONS, ids=mutate.EDITS)
def test_each_edit_changes_what_it_names(levels, edit):
    static, batch = levels
    level = first_level(batch)  # rocket-car-jump: a car (joints) and a thruster
    if edit is mutate.add_thruster:  # size s has one thruster slot: free it first
        thrusters = level.physics.thrusters.replace(active=jnp.zeros_like(level.physics.thrusters.active))
        level = level.replace(physics=level.physics.replace(thrusters=thrusters))
    if edit in (mutate.add_free_shape, mutate.add_joined_shape):  # every s slot is used: take off the car's wheel
        wheel = int(level.physics.joints.body_b[0])
        bodies = level.physics.bodies.replace(active=level.physics.bodies.active.at[wheel].set(False))
        joints_ = level.physics.joints.replace(active=jnp.zeros_like(level.physics.joints.active))
        level = level.replace(physics=level.physics.replace(bodies=bodies, joints=joints_))
    edited, possible = jax.jit(functools.partial(edit, static))(jax.random.key(3), level)
    assert bool(possible)
    b0, b1 = level.physics.bodies, edited.physics.bodies
    t0, t1 = level.physics.thrusters, edited.physics.thrusters
    changes = {
        "move": not np.allclose(b0.position, b1.position) and np.allclose(b0.angle, b1.angle),
        "rotate_group": not np.allclose(b0.angle, b1.angle),
        "resize": not np.allclose(b0.vertices, b1.vertices) or not np.allclose(b0.radius, b1.radius),
        "swap_roles": not np.array_equal(b0.role, b1.role),
        "toggle_fixation": int(np.sum(b0.fixed != b1.fixed)) == 1,
        "add_thruster": int(t1.active.sum()) == int(t0.active.sum()) + 1,
        "remove_thruster": int(t1.active.sum()) == int(t0.active.sum()) - 1,
        "add_free_shape": int(b1.active.sum()) == int(b0.active.sum()) + 1 and joints(edited) == joints(level),
        "add_joined_shape": int(b1.active.sum()) == int(b0.active.sum()) + 1 and joints(edited) == joints(level) + 1,
    }
    assert changes[edit.__name__]
