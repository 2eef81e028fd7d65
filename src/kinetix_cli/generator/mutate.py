"""ACCEL's level edits: `mutate_level(static, key, level, edits) -> Level`, pure and jittable.

Each edit is one of (uniformly): add a free shape, add a shape joined to an existing one, move a shape, rotate a
shape, resize a free shape, swap the roles of two shapes, toggle a shape's fixation, add a thruster, remove a
thruster (the reference's list). Added shapes come from the generator's own additions (`sampler.add_free_shape`,
`sampler.add_connected_shape`: best of several proposals, the size's distribution), after which the slots are
shuffled again as a generated level's are. A shape moves and rotates together with every shape
joined to it (its joint-connected group), so joints stay closed; resizing is limited to shapes without joints (a
joint anchor would no longer sit where the other body holds it), and a thruster on a resized shape keeps its
place relative to the outline. An edit that leaves the level invalid (`sampler.is_valid`: green and blue present, a
working actuator, no deep overlap) or that finds nothing to edit is dropped, so every mutation of a valid level
is valid.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp

from engine import ARENA_TOP, FLOOR_TOP, NUM_ARENA_POLYGONS, SIZES, Static, rotate
from kinetix_cli.constants import NUM_THRUSTER_BINDINGS
from kinetix_cli.env.level import Level
from kinetix_cli.generator import sampler
from kinetix_cli.generator.sampler import WORLD, SamplerConfig, Shape, is_valid

EDITS = (
    "add free shape",
    "add joined shape",
    "move",
    "rotate",
    "resize",
    "swap roles",
    "toggle fixation",
    "add thruster",
    "remove thruster",
)
"""The edit kinds, in the order `edit_level` indexes them."""
MOVE_STD = 0.3
"""Standard deviation of a move, each axis [m]."""
ROTATE_MAX = math.pi / 4
"""Largest rotation of an edit [rad]."""
RESIZE = (0.7, 1.4)
"""Range of the scale factor of a resize."""


def shapes(level: Level) -> jax.Array:
    """(N,) bool: active bodies that are not the arena."""
    active = level.physics.bodies.active
    return active & (jnp.arange(active.shape[0]) >= NUM_ARENA_POLYGONS)


def joined_group(level: Level, body: jax.Array) -> jax.Array:
    """(N,) bool: `body` and every body connected to it through active joints."""
    joints = level.physics.joints
    n = level.physics.bodies.active.shape[0]
    link = jnp.zeros((n, n), bool).at[joints.body_a, joints.body_b].max(joints.active)
    link = link | link.T
    grow = lambda _, group: group | jnp.any(link & group[None, :], axis=1)  # noqa: E731 (one joint further)
    return jax.lax.fori_loop(0, n - 1, grow, jnp.arange(n) == body)


def pick(key: jax.Array, mask: jax.Array) -> tuple[jax.Array, jax.Array]:
    """(a uniformly chosen index where `mask`, whether there was any)."""
    index = jax.random.choice(key, mask.shape[0], p=mask / jnp.maximum(mask.sum(), 1))
    return index, jnp.any(mask)


def distribution(static: Static) -> SamplerConfig:
    """The generator's distribution for levels of size `static` (the reference's defaults for other sizes)."""
    names = [name for name, size in SIZES.items() if size == static]
    return sampler.default_config(names[0]) if names else SamplerConfig()


def add_shape(static: Static, key: jax.Array, level: Level, joined: bool) -> tuple[Level, jax.Array]:
    """A new shape where the generator would put one: free, or `joined` to an existing shape (revolute or fixed
    joint, maybe a motor). Found: whether a slot (and for a joined shape a joint) was free and a proposal fitted."""
    k_add, k_shuffle = jax.random.split(key)
    level = sampler.compact_slots(static, level)
    active = level.physics.bodies.active
    draft = sampler.Draft(
        level,
        polygons=jnp.sum(active[NUM_ARENA_POLYGONS : static.num_polygons]).astype(jnp.int32),
        circles=jnp.sum(active[static.num_polygons :]).astype(jnp.int32),
        joints=jnp.sum(level.physics.joints.active).astype(jnp.int32),
        thrusters=jnp.sum(level.physics.thrusters.active).astype(jnp.int32),
    )
    config = distribution(static)
    if joined:
        added = sampler.add_connected_shape(static, config, k_add, draft, shapes(level))
    else:
        added = sampler.add_free_shape(static, config, k_add, draft)
    found = added.polygons + added.circles > draft.polygons + draft.circles
    return sampler.shuffle_slots(static, k_shuffle, added.level), found


def add_free_shape(static: Static, key: jax.Array, level: Level) -> tuple[Level, jax.Array]:
    """A new free shape (`add_shape`)."""
    return add_shape(static, key, level, joined=False)


def add_joined_shape(static: Static, key: jax.Array, level: Level) -> tuple[Level, jax.Array]:
    """A new shape joined to an existing one (`add_shape`)."""
    return add_shape(static, key, level, joined=True)


def move(static: Static, key: jax.Array, level: Level) -> tuple[Level, jax.Array]:
    """Shift a shape and its joined group by a random offset, kept inside the arena."""
    k_body, k_delta = jax.random.split(key)
    body, found = pick(k_body, shapes(level))
    group = joined_group(level, body)
    b = level.physics.bodies
    delta = jax.random.normal(k_delta, (2,)) * MOVE_STD
    position = jnp.where(group[:, None], b.position + delta, b.position)
    inside = (position[:, 0] > 0) & (position[:, 0] < WORLD) & (position[:, 1] > FLOOR_TOP)
    inside = jnp.all(inside | ~group) & jnp.all((position[:, 1] < ARENA_TOP) | ~group)
    bodies = b.replace(position=position)
    return level.replace(physics=level.physics.replace(bodies=bodies)), found & inside


def rotate_group(static: Static, key: jax.Array, level: Level) -> tuple[Level, jax.Array]:
    """Turn a shape and its joined group rigidly about the shape's centre."""
    k_body, k_angle = jax.random.split(key)
    body, found = pick(k_body, shapes(level))
    group = joined_group(level, body)
    b = level.physics.bodies
    turn = jax.random.uniform(k_angle, minval=-ROTATE_MAX, maxval=ROTATE_MAX)
    pivot = b.position[body]
    turned = pivot + jax.vmap(rotate, in_axes=(0, None))(b.position - pivot, turn)
    bodies = b.replace(
        position=jnp.where(group[:, None], turned, b.position), angle=jnp.where(group, b.angle + turn, b.angle)
    )
    return level.replace(physics=level.physics.replace(bodies=bodies)), found


def resize(static: Static, key: jax.Array, level: Level) -> tuple[Level, jax.Array]:
    """Scale a shape without joints (vertices or radius, and its thrusters' anchors) by a random factor."""
    k_body, k_scale = jax.random.split(key)
    joints = level.physics.joints
    n = level.physics.bodies.active.shape[0]
    jointed = jnp.zeros(n, bool).at[joints.body_a].max(joints.active).at[joints.body_b].max(joints.active)
    body, found = pick(k_body, shapes(level) & ~jointed)
    scale = jax.random.uniform(k_scale, minval=RESIZE[0], maxval=RESIZE[1])
    b = level.physics.bodies
    config = SamplerConfig()
    radius = b.radius[body] * scale
    half = jnp.abs(b.vertices[body, 2]) * scale
    big_enough = jnp.where(
        b.radius[body] > 0, radius >= config.radius[0] / 2, jnp.all(half >= config.half_extent[0] / 2)
    )
    small_enough = Shape(b.radius[body] > 0, half, radius).extent() <= (ARENA_TOP - FLOOR_TOP) / 2
    bodies = b.replace(vertices=b.vertices.at[body].multiply(scale), radius=b.radius.at[body].set(radius))
    th = level.physics.thrusters
    anchor = jnp.where((th.body == body)[:, None], th.anchor * scale, th.anchor)
    physics = level.physics.replace(bodies=bodies, thrusters=th.replace(anchor=anchor))
    return level.replace(physics=physics), found & big_enough & small_enough


def swap_roles(static: Static, key: jax.Array, level: Level) -> tuple[Level, jax.Array]:
    """Exchange the roles of two shapes of different roles."""
    k_a, k_b = jax.random.split(key)
    role = level.physics.bodies.role
    a, found_a = pick(k_a, shapes(level))
    b, found_b = pick(k_b, shapes(level) & (role != role[a]))
    new_role = role.at[a].set(role[b]).at[b].set(role[a])
    bodies = level.physics.bodies.replace(role=new_role)
    return level.replace(physics=level.physics.replace(bodies=bodies)), found_a & found_b


def toggle_fixation(static: Static, key: jax.Array, level: Level) -> tuple[Level, jax.Array]:
    """Fix a movable shape or free a fixed one."""
    body, found = pick(key, shapes(level))
    b = level.physics.bodies
    bodies = b.replace(fixed=b.fixed.at[body].set(~b.fixed[body]))
    return level.replace(physics=level.physics.replace(bodies=bodies)), found


def add_thruster(static: Static, key: jax.Array, level: Level) -> tuple[Level, jax.Array]:
    """A thruster in a free slot, on a movable shape, pointing through its centre, bound to a random action."""
    k_body, k_anchor, k_flip, k_power, k_bind = jax.random.split(key, 5)
    b, th = level.physics.bodies, level.physics.thrusters
    body, found = pick(k_body, shapes(level) & ~b.fixed)
    slot, room = jnp.argmax(~th.active), jnp.any(~th.active)  # the first free slot
    shape = Shape(b.radius[body] > 0, jnp.abs(b.vertices[body, 2]), b.radius[body])
    anchor = shape.local_point(k_anchor)
    direction = jnp.arctan2(-anchor[1], -anchor[0]) + math.pi * jax.random.bernoulli(k_flip)
    config = SamplerConfig()
    power = shape.mass(config.density) * 2.0 * jax.random.uniform(k_power, minval=0.5, maxval=2.0)
    th = th.replace(
        body=th.body.at[slot].set(body),
        anchor=th.anchor.at[slot].set(anchor),
        angle=th.angle.at[slot].set(direction),
        power=th.power.at[slot].set(power),
        active=th.active.at[slot].set(True),
    )
    binding = jax.random.randint(k_bind, (), 0, NUM_THRUSTER_BINDINGS)
    bindings = level.bindings.replace(thruster=level.bindings.thruster.at[slot].set(binding))
    return level.replace(physics=level.physics.replace(thrusters=th), bindings=bindings), found & room


def remove_thruster(static: Static, key: jax.Array, level: Level) -> tuple[Level, jax.Array]:
    """Switch off one active thruster."""
    th = level.physics.thrusters
    slot, found = pick(key, th.active)
    th = th.replace(active=th.active.at[slot].set(False))
    return level.replace(physics=level.physics.replace(thrusters=th)), found


_EDIT_FUNCTIONS = (
    add_free_shape,
    add_joined_shape,
    move,
    rotate_group,
    resize,
    swap_roles,
    toggle_fixation,
    add_thruster,
    remove_thruster,
)


def edit_level(static: Static, key: jax.Array, level: Level) -> Level:
    """One random edit of `level` (uniform over `EDITS`), or `level` itself when the edit finds nothing to change
    or would make it invalid."""
    k_kind, k_edit = jax.random.split(key)
    kind = jax.random.randint(k_kind, (), 0, len(_EDIT_FUNCTIONS))
    edited, possible = jax.lax.switch(
        kind, [lambda k, lv, f=f: f(static, k, lv) for f in _EDIT_FUNCTIONS], k_edit, level
    )
    keep = possible & is_valid(static, edited)
    return jax.tree.map(lambda new, old: jnp.where(keep, new, old), edited, level)


def mutate_level(static: Static, key: jax.Array, level: Level, edits: int) -> Level:
    """`edits` successive random edits of one level (`edit_level`)."""
    level, _ = jax.lax.scan(lambda lv, k: (edit_level(static, k, lv), None), level, jax.random.split(key, edits))
    return level
