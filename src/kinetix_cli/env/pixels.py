"""The ``pixels`` observation: a small top-down RGB picture of one scene, rasterised on the device.

The image is (125, 125, 3) float32 in [0, 1] at 25 px per metre over the world x in [0, 5] m, y in [0, 5] m;
row 0 is the top (y = 5), column 0 the left (x = 0). Each pixel is sampled once at its centre
((col + 0.5) / 25, 5 - (row + 0.5) / 25); there is no anti-aliasing.

Layers, later on top: the background (white), the active bodies in slot order (polygons then circles; the
floor is polygon slot 0 with its top edge at y = 0.4, the walls and ceiling lie outside the view), then a
dot of radius `MARKER_RADIUS_PX` at every active joint's anchor, then one at every active thruster's anchor.

Colours (RGB 0..255, from `kinetix_cli.env.colours`, shared with `kinetix_cli.viz.render`):

- bodies by role: neutral (160, 160, 160), green (0, 204, 0), blue (0, 102, 204), red (255, 102, 102);
  a fixed neutral body (80, 80, 80), a fixed body with a role its role colour x 0.5.
- joints: a motor bound to action 0..3 `MOTOR_COLOURS`, an auto motor `AUTO_MOTOR_COLOUR`, a joint without
  a motor (revolute or fixed) `PLAIN_JOINT_COLOUR`.
- thrusters: by binding 0..1 `THRUSTER_COLOURS`.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from engine import Static, rotate, world_polygons
from kinetix_cli.env.colours import (
    AUTO_MOTOR_COLOUR,
    BACKGROUND,
    FIXED_NEUTRAL,
    FIXED_ROLE_SCALE,
    MOTOR_COLOURS,
    PLAIN_JOINT_COLOUR,
    ROLE_COLOURS,
    THRUSTER_COLOURS,
)
from kinetix_cli.env.level import Bindings

RESOLUTION = 125
"""Image height and width [px]."""
PIXELS_PER_METRE = 25.0
VIEW_TOP = RESOLUTION / PIXELS_PER_METRE
"""World y of the top image edge [m]; the view is x in [0, 5], y in [0, 5]."""
MARKER_RADIUS_PX = 2.0
"""Radius of the joint and thruster dots [px]."""


def _rgb(colours) -> jax.Array:
    """(K, 3) float32 in [0, 1] from 0..255 tuples."""
    return jnp.asarray(colours, jnp.float32).reshape(-1, 3) / 255.0


def body_colours(bodies) -> jax.Array:
    """(N, 3) float32 fill colour in [0, 1] of every body slot (role, darker when fixed)."""
    role = _rgb(ROLE_COLOURS)[bodies.role]
    fixed = jnp.where((bodies.role == 0)[:, None], _rgb(FIXED_NEUTRAL), role * FIXED_ROLE_SCALE)
    return jnp.where(bodies.fixed[:, None], fixed, role)


def joint_colours(joints, bindings: Bindings) -> jax.Array:
    """(J, 3) float32 dot colour in [0, 1] of every joint slot (motor binding, auto motor, or no motor)."""
    motor = joints.motor_on & ~joints.fixed
    bound = _rgb(MOTOR_COLOURS)[jnp.clip(bindings.motor, 0, len(MOTOR_COLOURS) - 1)]
    colour = jnp.where(bindings.motor_auto[:, None], _rgb(AUTO_MOTOR_COLOUR), bound)
    return jnp.where(motor[:, None], colour, _rgb(PLAIN_JOINT_COLOUR))


def pixel_centres() -> tuple[jax.Array, jax.Array]:
    """World x (W,) of the pixel columns and y (H,) of the pixel rows at their centres [m]."""
    centres = (jnp.arange(RESOLUTION, dtype=jnp.float32) + 0.5) / PIXELS_PER_METRE
    return centres, VIEW_TOP - centres


def _layers(static: Static, physics, bindings: Bindings):
    """Every drawn layer in paint order (L = N + J + T) as 4 half-planes and a disc; a pixel centre q is
    covered when n_k . q <= c_k for every k and |q - centre|^2 <= r^2.

    Polygons use their valid edges (an invalid edge is n = 0, c = 1) and an unbounded disc; circles and
    markers use no half-planes and their disc. Returns normals (L, 4, 2), offsets (L, 4) [m], centres (L, 2)
    [m], squared radii (L,) [m^2], active (L,) bool and colours (L, 3) in [0, 1].
    """
    p = static.num_polygons
    bodies, joints, thrusters = physics.bodies, physics.joints, physics.thrusters
    verts, normals, valid = world_polygons(static, bodies)
    offsets = jnp.where(valid, jnp.sum(normals * verts, axis=-1), 1.0)
    normals = jnp.where(valid[..., None], normals, 0.0)
    j, t = joints.active.shape[0], thrusters.active.shape[0]
    k = bodies.radius.shape[0] - p + j + t  # layers drawn as discs only
    a = joints.body_a
    joint_at = bodies.position[a] + rotate(joints.anchor_a, bodies.angle[a])
    tb = thrusters.body
    thruster_at = bodies.position[tb] + rotate(thrusters.anchor, bodies.angle[tb])
    marker2 = jnp.full((j + t,), (MARKER_RADIUS_PX / PIXELS_PER_METRE) ** 2, jnp.float32)
    radius2 = jnp.concatenate([jnp.full((p,), jnp.inf, jnp.float32), bodies.radius[p:] ** 2, marker2])
    colours = jnp.concatenate(
        [
            body_colours(bodies),
            joint_colours(joints, bindings),
            _rgb(THRUSTER_COLOURS)[jnp.clip(bindings.thruster, 0, len(THRUSTER_COLOURS) - 1)],
        ]
    )
    return (
        jnp.concatenate([normals, jnp.zeros((k, 4, 2))]),
        jnp.concatenate([offsets, jnp.ones((k, 4))]),
        jnp.concatenate([bodies.position, joint_at, thruster_at]),
        radius2,
        jnp.concatenate([bodies.active, joints.active, thrusters.active]),
        colours,
    )


def pixel_observation(static: Static, physics, bindings: Bindings) -> jax.Array:
    """(125, 125, 3) float32 RGB in [0, 1] of one scene (layout and colours in the module docstring).

    A scan over the L = N + J + T layers paints each layer's index onto an (H, W) image (~13 flops per pixel
    and layer); one palette lookup then gives the colours. Jittable, vmappable. (Measured in `kinetix bench env`
    on CPU, this runs 1-7x faster than one pass over an (H, W, L) array or painting RGB layer by layer.)
    """
    xs, ys = pixel_centres()
    x, y = xs[None, :], ys[:, None]  # broadcast over (H, W)

    def paint(top, layer):
        index, normal, offset, centre, r2, on = layer
        inside = on
        for e in range(4):
            inside = inside & (normal[e, 0] * x + normal[e, 1] * y <= offset[e])
        dx, dy = x - centre[0], y - centre[1]
        inside = inside & (dx * dx + dy * dy <= r2)
        return jnp.where(inside, index, top), None

    normals, offsets, centres, radius2, active, colours = _layers(static, physics, bindings)
    indices = jnp.arange(1, colours.shape[0] + 1, dtype=jnp.int32)
    top = jnp.zeros((RESOLUTION, RESOLUTION), jnp.int32)  # 0 = background, else 1 + layer index
    top, _ = jax.lax.scan(paint, top, (indices, normals, offsets, centres, radius2, active))
    palette = jnp.concatenate([_rgb(BACKGROUND), colours])
    return palette[top]
