"""Procedural levels: `sample_level(static, config, key) -> Level`, pure, jittable and vmappable.

Follows the reference Kinetix distribution (numbers in `SamplerConfig`), as a fixed recipe of additions so that
one compile serves every key:

1. an empty arena whose floor is neutral, blue or red;
2. two free shapes, green and blue (at least one of them movable);
3. forced control, uniformly one of: a thruster, a motor (a new shape hinged to green or blue), or both;
4. `P + C - 7` fill tries (0 for s, 2 for m, 9 for l): a connected shape, a free shape, or nothing;
5. `T - 1` tries to add another thruster;
6. green and blue swap roles with probability 1/2; 7. the entity slots are shuffled.

With `SamplerConfig.like` a level is drawn like a smaller size in this size's slots: that size's counts of tries
(and nothing fixed when like s), drawn per level, so one compile serves a mix of sizes.

Every addition draws `candidates` proposals and keeps the one with the fewest overlapping contact points; an
addition whose best proposal still penetrates deeper than `max_penetration`, or that finds no free slot, is
skipped. `is_valid` says whether the result is a task (green and blue present, a working actuator).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import jax
import jax.numpy as jnp
from flax import struct

from engine import (
    ARENA_RIGHT,
    ARENA_TOP,
    FLOOR_TOP,
    NUM_ARENA_POLYGONS,
    SIZES,
    Scene,
    Static,
    collidable_pairs,
    collide,
    pair_table,
    rotate,
)
from kinetix_cli.constants import BLUE, GREEN, NEUTRAL, NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS, RED
from kinetix_cli.env.level import Bindings, Level, empty_bindings, make_level

WORLD = ARENA_RIGHT
"""Arena width [m]: shapes stay in x in [0, WORLD]; the ceiling is at y = ARENA_TOP."""


@dataclasses.dataclass(frozen=True)
class SamplerConfig:
    """The generator's distribution (defaults: the reference's).

    Attributes:
        floor_roles: probabilities of the floor being neutral, green, blue, red.
        candidates: proposals per addition; the one with the fewest overlapping contacts is kept.
        max_penetration: an addition whose best proposal overlaps deeper than this is skipped [m].
        circle_prob: a new shape is a circle (else a rectangle) with this probability.
        half_extent: range of rectangle half-extents [m]; one axis is doubled with `long_prob`.
        long_prob: probability that one rectangle axis is doubled.
        radius: range of circle radii [m].
        fixate: whether free shapes may be fixed (the reference fixes nothing at size s).
        fixate_base, fixate_per_kg: a free shape is fixed with probability min(1, base + per_kg * mass).
        halves_prob: probability that green starts in the left half and blue in the right half.
        red_weight: weight of red against neutral (1) for a new shape's role while no red exists.
        connected_prob, free_prob: a fill try adds a connected shape, a free shape, or (the rest) nothing.
        revolute_prob: a connected shape's joint is revolute (else fixed); the first two joints always are.
        motor_prob: a revolute joint gets a motor.
        limits_prob: a revolute joint gets limits (lower U[-pi, 0], upper U[0, pi] around its initial angle).
        motor_speed, motor_power: ranges of the motor scales (power is 1 when a circle is involved).
        thruster_prob: probability of each extra thruster try.
        thruster_power: thruster power = mass * 2 * u, u drawn uniformly from this range [1].
        thruster_com_prob: a thruster pushes through the centre of mass (else in a uniform direction).
        swap_prob: probability that green and blue swap roles.
        density, friction, restitution: material of every new shape.
        like: draw each level like one of these sizes, each equally likely, in the slots of the static it is
            sampled for (no larger than it): that size's fill tries (`P + C - 7`) and extra thruster tries
            (`T - 1`), nothing fixed when like 's' (then `fixate` is ignored). Empty: like the static's own size.
            One compile serves the mix, so a single run trains on levels of several sizes at once.
    """

    floor_roles: tuple[float, float, float, float] = (0.90, 0.0, 0.02, 0.08)
    candidates: int = 8
    max_penetration: float = 0.02
    circle_prob: float = 0.5
    half_extent: tuple[float, float] = (0.05, 0.354)
    long_prob: float = 0.3
    radius: tuple[float, float] = (0.1, 0.4)
    fixate: bool = True
    fixate_base: float = 0.02
    fixate_per_kg: float = 4.0
    halves_prob: float = 0.5
    red_weight: float = 1.0 / 3.0
    connected_prob: float = 0.35
    free_prob: float = 0.35
    revolute_prob: float = 0.5
    motor_prob: float = 0.8
    limits_prob: float = 0.4
    motor_speed: tuple[float, float] = (0.4, 3.0)
    motor_power: tuple[float, float] = (1.0, 3.0)
    thruster_prob: float = 0.3
    thruster_power: tuple[float, float] = (0.5, 2.0)
    thruster_com_prob: float = 0.8
    swap_prob: float = 0.5
    density: float = 1.0
    friction: float = 1.0
    restitution: float = 0.0
    like: tuple[str, ...] = ()


def default_config(size: str) -> SamplerConfig:
    """The reference settings for a size: nothing is fixed at size s."""
    return SamplerConfig(fixate=size != "s")


@struct.dataclass
class Draft:
    """A level under construction: the level and how many slots each kind has used."""

    level: Level
    polygons: jax.Array  # () int32 non-arena polygon slots used
    circles: jax.Array  # () int32
    joints: jax.Array  # () int32
    thrusters: jax.Array  # () int32


@struct.dataclass
class Shape:
    """One proposed shape in its body frame: a rectangle (half-extents) or a circle (radius)."""

    is_circle: jax.Array  # () bool
    half: jax.Array  # (2,) [m]
    radius: jax.Array  # () [m]

    def extent(self) -> jax.Array:
        """Bounding radius about the centre [m]."""
        return jnp.where(self.is_circle, self.radius, jnp.linalg.norm(self.half))

    def mass(self, density: float) -> jax.Array:
        """[kg] at uniform `density` [kg/m^2]."""
        return density * jnp.where(self.is_circle, math.pi * self.radius**2, 4.0 * self.half[0] * self.half[1])

    def local_point(self, key: jax.Array, inset: float = 0.8) -> jax.Array:
        """(2,) a uniform point inside the shape, shrunk by `inset` [m]."""
        k_box, k_r, k_theta = jax.random.split(key, 3)
        box = jax.random.uniform(k_box, (2,), minval=-1.0, maxval=1.0) * self.half
        r = self.radius * jnp.sqrt(jax.random.uniform(k_r))
        theta = jax.random.uniform(k_theta, maxval=2 * math.pi)
        disc = r * jnp.array([jnp.cos(theta), jnp.sin(theta)])
        return inset * jnp.where(self.is_circle, disc, box)


# --- proposals -----------------------------------------------------------------------------------


def random_shape(config: SamplerConfig, key: jax.Array) -> Shape:
    """A rectangle or circle with the configured sizes."""
    k_kind, k_half, k_long, k_axis, k_radius = jax.random.split(key, 5)
    half = jax.random.uniform(k_half, (2,), minval=config.half_extent[0], maxval=config.half_extent[1])
    long_axis = jax.random.bernoulli(k_long, config.long_prob) & (jnp.arange(2) == jax.random.randint(k_axis, (), 0, 2))
    half = jnp.where(long_axis, 2.0 * half, half)
    radius = jax.random.uniform(k_radius, minval=config.radius[0], maxval=config.radius[1])
    return Shape(jax.random.bernoulli(k_kind, config.circle_prob), half, radius)


def free_slot(static: Static, draft: Draft, want_circle: jax.Array) -> tuple[jax.Array, jax.Array, jax.Array]:
    """The body slot for a new shape: the wanted kind if it has room, else the other kind.

    Returns (slot, is_circle, available) with slot an int32 body index.
    """
    poly_room = draft.polygons < static.num_polygons - NUM_ARENA_POLYGONS
    circle_room = draft.circles < static.num_circles
    is_circle = jnp.where(want_circle, circle_room, ~poly_room)
    slot = jnp.where(is_circle, static.slot("circle", draft.circles), static.slot("polygon", draft.polygons))
    return slot.astype(jnp.int32), is_circle, poly_room | circle_room


def place_body(draft: Draft, slot, shape: Shape, position, angle, role, fixed, config: SamplerConfig) -> Draft:
    """Write `shape` into body `slot` and count the slot as used."""
    b = draft.level.physics.bodies
    vertices = jnp.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]) * shape.half
    bodies = b.replace(
        position=b.position.at[slot].set(position),
        angle=b.angle.at[slot].set(angle),
        vertices=b.vertices.at[slot].set(jnp.where(shape.is_circle, 0.0, vertices)),
        num_vertices=b.num_vertices.at[slot].set(jnp.where(shape.is_circle, 0, 4)),
        radius=b.radius.at[slot].set(jnp.where(shape.is_circle, shape.radius, 0.0)),
        density=b.density.at[slot].set(config.density),
        friction=b.friction.at[slot].set(config.friction),
        restitution=b.restitution.at[slot].set(config.restitution),
        active=b.active.at[slot].set(True),
        fixed=b.fixed.at[slot].set(fixed),
        role=b.role.at[slot].set(role),
    )
    physics = draft.level.physics.replace(bodies=bodies)
    return draft.replace(
        level=draft.level.replace(physics=physics),
        polygons=draft.polygons + jnp.where(shape.is_circle, 0, 1),
        circles=draft.circles + jnp.where(shape.is_circle, 1, 0),
    )


def overlap(static: Static, level: Level) -> tuple[jax.Array, jax.Array]:
    """(overlapping contact points, deepest penetration [m]) between collidable bodies of a level."""
    physics = level.physics
    table = pair_table(static)
    manifold = collide(static, physics.bodies, jnp.zeros(table.num_pairs))
    collidable = collidable_pairs(static, physics.bodies, physics.joints)[table.point_pair]
    penetration = jnp.where(collidable & manifold.valid, -manifold.separation, 0.0)
    return jnp.sum(penetration > 0), jnp.max(penetration, initial=0.0)


def best_proposal(static: Static, config: SamplerConfig, key: jax.Array, draft: Draft, propose) -> Draft:
    """Draw `config.candidates` proposals `propose(key, draft) -> (draft, possible)` and keep the one with the
    fewest overlapping contacts, or `draft` unchanged if none is possible and shallow enough."""
    keys = jax.random.split(key, config.candidates)
    drafts, possible = jax.vmap(propose, in_axes=(0, None))(keys, draft)
    count, deepest = jax.vmap(functools.partial(overlap, static))(drafts.level)
    acceptable = possible & (deepest <= config.max_penetration)
    score = jnp.where(acceptable, count + deepest, jnp.inf)
    best = jnp.argmin(score)
    chosen = jax.tree.map(lambda x: x[best], drafts)
    return jax.tree.map(lambda new, old: jnp.where(acceptable[best], new, old), chosen, draft)


def sample_position(key: jax.Array, extent, x_range=(0.0, WORLD)) -> jax.Array:
    """(2,) a centre that keeps a shape of bounding radius `extent` inside the arena and `x_range` [m]."""
    low = jnp.array([jnp.maximum(x_range[0], extent), FLOOR_TOP + extent])
    high = jnp.array([jnp.minimum(x_range[1], WORLD - extent), ARENA_TOP - extent])
    return low + jax.random.uniform(key, (2,)) * jnp.maximum(high - low, 0.0)


def random_role(config: SamplerConfig, key: jax.Array, draft: Draft, may_be_red) -> jax.Array:
    """Neutral, or red with weight `red_weight` while the level has no red body yet."""
    has_red = jnp.any(draft.level.physics.bodies.active & (draft.level.physics.bodies.role == RED))
    p_red = config.red_weight / (1.0 + config.red_weight)
    red = may_be_red & ~has_red & jax.random.bernoulli(key, p_red)
    return jnp.where(red, RED, NEUTRAL)


# --- additions -----------------------------------------------------------------------------------


def add_free_shape(
    static: Static, config: SamplerConfig, key: jax.Array, draft: Draft, role=None, x_range=None, fixate=None
):
    """A free shape anywhere in the arena (or in `x_range`), fixed with a probability growing with its mass when
    `fixate` (default: `config.fixate`)."""
    fixate = config.fixate if fixate is None else fixate

    def propose(k, d):
        k_shape, k_pos, k_angle, k_fix, k_role = jax.random.split(k, 5)
        shape = random_shape(config, k_shape)
        slot, is_circle, available = free_slot(static, d, shape.is_circle)
        shape = shape.replace(is_circle=is_circle)
        position = sample_position(k_pos, shape.extent(), x_range or (0.0, WORLD))
        angle = jax.random.uniform(k_angle, maxval=2 * math.pi)
        p_fixed = jnp.minimum(1.0, config.fixate_base + config.fixate_per_kg * shape.mass(config.density))
        fixed = fixate & jax.random.bernoulli(k_fix, p_fixed)
        new_role = random_role(config, k_role, d, True) if role is None else role
        return place_body(d, slot, shape, position, angle, new_role, fixed, config), available

    return best_proposal(static, config, key, draft, propose)


def add_connected_shape(
    static: Static, config: SamplerConfig, key: jax.Array, draft: Draft, parents: jax.Array, force_motor: bool = False
):
    """A new movable shape joined to one of the `parents` (N,) bool bodies by a revolute or fixed joint.

    With `force_motor` the joint is revolute with a motor; otherwise the configured probabilities apply.
    """

    def propose(k, d):
        keys = jax.random.split(k, 14)
        bodies = d.level.physics.bodies
        parent = jax.random.choice(keys[0], bodies.active.shape[0], p=parents / jnp.maximum(parents.sum(), 1))
        shape = random_shape(config, keys[1])
        slot, is_circle, shape_room = free_slot(static, d, shape.is_circle)
        shape = shape.replace(is_circle=is_circle)
        parent_shape = Shape(bodies.radius[parent] > 0, jnp.abs(bodies.vertices[parent, 2]), bodies.radius[parent])
        anchor_a = parent_shape.local_point(keys[2])
        anchor_b = shape.local_point(keys[3])
        angle = jax.random.uniform(keys[4], maxval=2 * math.pi)
        world_anchor = bodies.position[parent] + rotate(anchor_a, bodies.angle[parent])
        position = world_anchor - rotate(anchor_b, angle)
        inside = (position[0] > 0.0) & (position[0] < WORLD) & (position[1] > FLOOR_TOP) & (position[1] < ARENA_TOP)

        j = d.joints
        revolute = force_motor | (j < 2) | jax.random.bernoulli(keys[5], config.revolute_prob)
        motor = revolute & (force_motor | jax.random.bernoulli(keys[6], config.motor_prob))
        limits = revolute & jax.random.bernoulli(keys[7], config.limits_prob)
        relative = angle - bodies.angle[parent]
        with_circle = is_circle | parent_shape.is_circle
        power = jnp.where(
            with_circle, 1.0, jax.random.uniform(keys[8], minval=config.motor_power[0], maxval=config.motor_power[1])
        )
        joints = d.level.physics.joints
        joints = joints.replace(
            body_a=joints.body_a.at[j].set(parent),
            body_b=joints.body_b.at[j].set(slot),
            anchor_a=joints.anchor_a.at[j].set(anchor_a),
            anchor_b=joints.anchor_b.at[j].set(anchor_b),
            fixed=joints.fixed.at[j].set(~revolute),
            ref_angle=joints.ref_angle.at[j].set(relative),
            motor_on=joints.motor_on.at[j].set(motor),
            motor_speed=joints.motor_speed.at[j].set(
                jax.random.uniform(keys[9], minval=config.motor_speed[0], maxval=config.motor_speed[1])
            ),
            motor_power=joints.motor_power.at[j].set(power),
            has_limits=joints.has_limits.at[j].set(limits),
            min_angle=joints.min_angle.at[j].set(relative + jax.random.uniform(keys[10], minval=-math.pi, maxval=0.0)),
            max_angle=joints.max_angle.at[j].set(relative + jax.random.uniform(keys[11], maxval=math.pi)),
            active=joints.active.at[j].set(True),
        )
        binding = jax.random.randint(keys[12], (), 0, NUM_MOTOR_BINDINGS)
        bindings = d.level.bindings.replace(motor=d.level.bindings.motor.at[j].set(binding))
        role = random_role(config, keys[13], d, ~jnp.isin(bodies.role[parent], jnp.array([GREEN, BLUE])))
        d = place_body(d, slot, shape, position, angle, role, False, config)
        physics = d.level.physics.replace(joints=joints)
        d = d.replace(level=d.level.replace(physics=physics, bindings=bindings), joints=j + 1)
        possible = shape_room & (j < static.num_joints) & jnp.any(parents) & inside
        return d, possible

    return best_proposal(static, config, key, draft, propose)


def add_thruster(static: Static, config: SamplerConfig, key: jax.Array, draft: Draft, hosts: jax.Array) -> Draft:
    """A thruster on one of the `hosts` (N,) bool bodies that is movable; power grows with the host's mass."""
    bodies = draft.level.physics.bodies
    hosts = hosts & bodies.active & ~bodies.fixed
    keys = jax.random.split(key, 7)
    host = jax.random.choice(keys[0], hosts.shape[0], p=hosts / jnp.maximum(hosts.sum(), 1))
    shape = Shape(bodies.radius[host] > 0, jnp.abs(bodies.vertices[host, 2]), bodies.radius[host])
    anchor = shape.local_point(keys[1])
    inward = jnp.arctan2(-anchor[1], -anchor[0]) + math.pi * jax.random.bernoulli(keys[2])
    through_com = jax.random.bernoulli(keys[3], config.thruster_com_prob) & (jnp.linalg.norm(anchor) > 1e-3)
    direction = jnp.where(through_com, inward, jax.random.uniform(keys[4], maxval=2 * math.pi))
    scale = jax.random.uniform(keys[5], minval=config.thruster_power[0], maxval=config.thruster_power[1])
    t = draft.thrusters
    ok = jnp.any(hosts) & (t < static.num_thrusters)
    th = draft.level.physics.thrusters
    th = th.replace(
        body=th.body.at[t].set(host),
        anchor=th.anchor.at[t].set(anchor),
        angle=th.angle.at[t].set(direction),
        power=th.power.at[t].set(shape.mass(config.density) * 2.0 * scale),
        active=th.active.at[t].set(True),
    )
    bindings = draft.level.bindings.replace(
        thruster=draft.level.bindings.thruster.at[t].set(jax.random.randint(keys[6], (), 0, NUM_THRUSTER_BINDINGS))
    )
    level = draft.level.replace(physics=draft.level.physics.replace(thrusters=th), bindings=bindings)
    new = draft.replace(level=level, thrusters=t + 1)
    return jax.tree.map(lambda a, b: jnp.where(ok, a, b), new, draft)


# --- the recipe ----------------------------------------------------------------------------------


@functools.cache
def empty_level(static: Static) -> Level:
    """The arena alone, with numpy leaves and the default engine constants (cached per size)."""
    return make_level(Scene().build_numpy(static), empty_bindings(static.num_joints, static.num_thrusters))


def role_mask(draft: Draft, *roles: int) -> jax.Array:
    """(N,) bool: active bodies with one of `roles`."""
    bodies = draft.level.physics.bodies
    return bodies.active & jnp.isin(bodies.role, jnp.array(roles))


def tries(static: Static) -> tuple[int, int]:
    """(fill tries, extra thruster tries) of a level of size `static`: `P + C - 7` and `T - 1`."""
    return static.num_polygons + static.num_circles - 7, static.num_thrusters - 1


def size_recipe(static: Static, config: SamplerConfig, key: jax.Array) -> tuple[jax.Array, jax.Array, jax.Array]:
    """(fill tries, extra thruster tries, whether free shapes may be fixed) of one level: those of `static`'s own
    size, or of a size drawn from `config.like`."""
    own = tries(static)
    if not config.like:
        return jnp.int32(own[0]), jnp.int32(own[1]), jnp.asarray(config.fixate)
    recipes = [tries(SIZES[name]) for name in config.like]
    for name, recipe in zip(config.like, recipes, strict=True):
        if recipe[0] > own[0] or recipe[1] > own[1]:
            raise ValueError(f"levels like size {name!r} do not fit the slots of a smaller size")
    pick = jax.random.randint(key, (), 0, len(config.like))
    table = jnp.array(recipes)
    fixate = jnp.array([n != "s" for n in config.like])
    return table[pick, 0], table[pick, 1], fixate[pick]


def sample_level(static: Static, config: SamplerConfig, key: jax.Array) -> Level:
    """One random level of size `static` (see the module docstring for the recipe)."""
    keys = iter(jax.random.split(key, 12))
    fill_tries, thruster_tries, fixate = size_recipe(static, config, jax.random.fold_in(key, 1))
    zero = jnp.zeros((), jnp.int32)
    draft = Draft(jax.tree.map(jnp.asarray, empty_level(static)), zero, zero, zero, zero)

    # 1. floor role
    floor_role = jax.random.choice(next(keys), len(config.floor_roles), p=jnp.asarray(config.floor_roles))
    bodies = draft.level.physics.bodies
    draft = draft.replace(
        level=draft.level.replace(
            physics=draft.level.physics.replace(bodies=bodies.replace(role=bodies.role.at[0].set(floor_role)))
        )
    )

    # 2. green and blue, in opposite halves with `halves_prob`; at least one movable
    halves = jax.random.bernoulli(next(keys), config.halves_prob)
    left = (0.0, jnp.where(halves, WORLD / 2, WORLD))
    right = (jnp.where(halves, WORLD / 2, 0.0), WORLD)
    draft = add_free_shape(static, config, next(keys), draft, role=GREEN, x_range=left, fixate=fixate)
    draft = add_free_shape(static, config, next(keys), draft, role=BLUE, x_range=right, fixate=fixate)
    draft = unfix_one_of_green_blue(next(keys), draft)

    # 3. forced control: 0 thruster, 1 motor, 2 both
    control = jax.random.randint(next(keys), (), 0, 3)
    goal = role_mask(draft, GREEN, BLUE)
    with_motor = add_connected_shape(static, config, next(keys), draft, goal, force_motor=True)
    draft = jax.tree.map(lambda a, b: jnp.where(control >= 1, a, b), with_motor, draft)
    with_thruster = add_thruster(static, config, next(keys), draft, goal)
    draft = jax.tree.map(lambda a, b: jnp.where(control != 1, a, b), with_thruster, draft)

    # 4. fill tries: a connected shape, a free shape or nothing (one compiled body, scanned)
    def fill(d: Draft, try_key: tuple[jax.Array, jax.Array]) -> tuple[Draft, None]:
        i, k = try_key
        k_pick, k_add = jax.random.split(k)
        u = jax.random.uniform(k_pick)
        shapes = d.level.physics.bodies.active.at[:NUM_ARENA_POLYGONS].set(False)
        connected = add_connected_shape(static, config, k_add, d, shapes)
        free = add_free_shape(static, config, k_add, d, fixate=fixate)
        pick = jnp.where(u < config.connected_prob, 0, jnp.where(u < config.connected_prob + config.free_prob, 1, 2))
        pick = jnp.where(i < fill_tries, pick, 2)  # a try beyond this level's count adds nothing
        return jax.tree.map(lambda *x: jnp.stack(x)[pick], connected, free, d), None

    max_fill, max_thrusters = tries(static)
    if max_fill > 0:
        draft, _ = jax.lax.scan(fill, draft, (jnp.arange(max_fill), jax.random.split(next(keys), max_fill)))

    # 5. extra thrusters
    def extra_thruster(d: Draft, try_key: tuple[jax.Array, jax.Array]) -> tuple[Draft, None]:
        i, k = try_key
        k_try, k_add = jax.random.split(k)
        shapes = d.level.physics.bodies.active.at[:NUM_ARENA_POLYGONS].set(False)
        more = add_thruster(static, config, k_add, d, shapes)
        add = jax.random.bernoulli(k_try, config.thruster_prob) & (i < thruster_tries)
        return jax.tree.map(lambda a, b: jnp.where(add, a, b), more, d), None

    if max_thrusters > 0:
        draft, _ = jax.lax.scan(
            extra_thruster, draft, (jnp.arange(max_thrusters), jax.random.split(next(keys), max_thrusters))
        )

    # 6. swap green and blue; 7. shuffle slots
    level = swap_green_blue(draft.level, jax.random.bernoulli(next(keys), config.swap_prob))
    return shuffle_slots(static, next(keys), level)


def unfix_one_of_green_blue(key: jax.Array, draft: Draft) -> Draft:
    """If green and blue are both fixed, free one of them (chosen at random)."""
    bodies = draft.level.physics.bodies
    goal = role_mask(draft, GREEN, BLUE)
    both_fixed = jnp.all(bodies.fixed | ~goal)
    pick = jnp.where(jax.random.bernoulli(key), GREEN, BLUE)
    fixed = jnp.where(both_fixed & goal & (bodies.role == pick), False, bodies.fixed)
    physics = draft.level.physics.replace(bodies=bodies.replace(fixed=fixed))
    return draft.replace(level=draft.level.replace(physics=physics))


def swap_green_blue(level: Level, swap: jax.Array) -> Level:
    """Exchange the green and blue roles of the shapes (not the arena) when `swap`."""
    role = level.physics.bodies.role
    shape = jnp.arange(role.shape[0]) >= NUM_ARENA_POLYGONS
    swapped = jnp.where(shape & (role == GREEN), BLUE, jnp.where(shape & (role == BLUE), GREEN, role))
    bodies = level.physics.bodies.replace(role=jnp.where(swap, swapped, role))
    return level.replace(physics=level.physics.replace(bodies=bodies))


def shuffle_slots(static: Static, key: jax.Array, level: Level) -> Level:
    """Permute the non-arena polygon slots, the circle slots, the joints and the thrusters at random, keeping every
    joint and thruster attached to the same bodies."""
    k_poly, k_circle, k_joint, k_thruster = jax.random.split(key, 4)
    p, c = static.num_polygons, static.num_circles
    return permute_slots(
        static,
        level,
        jax.random.permutation(k_poly, p - NUM_ARENA_POLYGONS),
        jax.random.permutation(k_circle, c),
        jax.random.permutation(k_joint, static.num_joints),
        jax.random.permutation(k_thruster, static.num_thrusters),
    )


def compact_slots(static: Static, level: Level) -> Level:
    """Move the active polygons, circles, joints and thrusters to the front of their slot ranges (in their order),
    as the recipe leaves a draft before `shuffle_slots`, so that `Draft` counts name the next free slots."""
    active = level.physics.bodies.active
    first_inactive = lambda mask: jnp.argsort(~mask, stable=True)  # noqa: E731
    return permute_slots(
        static,
        level,
        first_inactive(active[NUM_ARENA_POLYGONS : static.num_polygons]),
        first_inactive(active[static.num_polygons :]),
        first_inactive(level.physics.joints.active),
        first_inactive(level.physics.thrusters.active),
    )


def permute_slots(static: Static, level: Level, polygons, circles, joint_order, thruster_order) -> Level:
    """Reorder the non-arena polygon slots, the circle slots, the joints and the thrusters (each an int permutation
    of its range, new slot -> old slot), keeping every joint and thruster attached to the same bodies."""
    arena = static.slot("arena", jnp.arange(NUM_ARENA_POLYGONS))
    order = jnp.concatenate([arena, static.slot("polygon", polygons), static.slot("circle", circles)])
    new_slot = jnp.argsort(order)  # old body slot -> new body slot
    physics = level.physics
    bodies = jax.tree.map(lambda x: x[order], physics.bodies)
    joints = jax.tree.map(lambda x: x[joint_order], physics.joints)
    joints = joints.replace(body_a=new_slot[joints.body_a], body_b=new_slot[joints.body_b])
    thrusters = jax.tree.map(lambda x: x[thruster_order], physics.thrusters)
    thrusters = thrusters.replace(body=new_slot[thrusters.body])
    bindings = Bindings(
        motor=level.bindings.motor[joint_order],
        motor_auto=level.bindings.motor_auto[joint_order],
        thruster=level.bindings.thruster[thruster_order],
    )
    return level.replace(physics=physics.replace(bodies=bodies, joints=joints, thrusters=thrusters), bindings=bindings)


def is_valid(static: Static, level: Level, max_penetration: float = SamplerConfig.max_penetration) -> jax.Array:
    """() bool: green and blue present, a controllable motor or thruster that moves something, no deep overlap."""
    physics = level.physics
    bodies, joints, thrusters = physics.bodies, physics.joints, physics.thrusters
    green = jnp.any(bodies.active & (bodies.role == GREEN))
    blue = jnp.any(bodies.active & (bodies.role == BLUE))
    movable = bodies.active & ~bodies.fixed
    motor = joints.active & joints.motor_on & ~joints.fixed & ~level.bindings.motor_auto
    motor = motor & (movable[joints.body_a] | movable[joints.body_b])
    thruster = thrusters.active & movable[thrusters.body]
    _, deepest = overlap(static, level)
    return green & blue & (jnp.any(motor) | jnp.any(thruster)) & (deepest <= max_penetration)
