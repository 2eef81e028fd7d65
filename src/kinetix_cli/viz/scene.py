"""What a picture of one scene shows, as data: the arena, each shape with its fill and outline colour, each joint
and thruster with its colour, action and label, and the legend of the bindings in use. `render.render_frame`
paints it with Pillow; the level studio sends it to the browser as JSON (`scene_json`) and paints it on a canvas,
so both show the same colours and legend.

All points are world coordinates [m] (y up); colours are RGB tuples.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from engine import ARENA_LEFT, ARENA_RIGHT, ARENA_TOP, NUM_ARENA_POLYGONS
from kinetix_cli.constants import ACTION_WIDTH, NEUTRAL, NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS
from kinetix_cli.env.colours import (
    AUTO_MOTOR_COLOUR,
    BACKGROUND,
    FIXED_NEUTRAL,
    FIXED_ROLE_SCALE,
    MOTOR_COLOURS,
    ROLE_COLOURS,
    THRUSTER_COLOURS,
    Colour,
)

VIEW_X = (-0.1, 5.1)
"""World x range shown [m]."""
VIEW_Y = (0.0, 5.1)
"""World y range shown [m]."""
WALL_FILL: Colour = (225, 225, 225)
WALL_LINE: Colour = (50, 50, 50)


@dataclasses.dataclass(frozen=True)
class Wall:
    """An active arena wall or the ceiling: the visible strip outside the arena and its inner face."""

    slot: int
    strip: np.ndarray  # (4, 2)
    face: np.ndarray  # (2, 2)
    fill: Colour
    line: Colour


@dataclasses.dataclass(frozen=True)
class Shape:
    """A body's shape: a polygon (`points`, world vertices) or a circle (`centre`, `radius`, `angle` [rad])."""

    slot: int
    fill: Colour
    line: Colour
    points: np.ndarray | None = None  # (n, 2)
    centre: np.ndarray | None = None
    radius: float = 0.0
    angle: float = 0.0


@dataclasses.dataclass(frozen=True)
class Joint:
    """A joint at its world `anchor`: fixed, or revolute with its motor's colour (None: no motor), action and
    label (None without a motor or without actions)."""

    index: int
    anchor: np.ndarray
    fixed: bool
    colour: Colour | None = None
    action: float | None = None
    label: str | None = None


@dataclasses.dataclass(frozen=True)
class Thruster:
    """A thruster at its world `anchor`, pushing along `push` [rad], with its binding's colour and action."""

    index: int
    anchor: np.ndarray
    push: float
    colour: Colour
    action: float | None
    label: str


@dataclasses.dataclass(frozen=True)
class Scene:
    """Everything a picture of one scene shows, back to front: walls, shapes (the floor first, fixed shapes
    before movable ones), joints, thrusters; and the legend (text, colour) of the bindings in use."""

    walls: list[Wall]
    shapes: list[Shape]
    joints: list[Joint]
    thrusters: list[Thruster]
    legend: list[tuple[str, Colour]]


# --- colours -------------------------------------------------------------------------------------
def scaled(colour: Colour, factor: float) -> Colour:
    return tuple(int(round(min(255.0, c * factor))) for c in colour)


def mix(a: Colour, b: Colour, t: float) -> Colour:
    """(1 - t) a + t b."""
    return tuple(int(round((1 - t) * x + t * y)) for x, y in zip(a, b, strict=True))


def body_fill(role: int, fixed: bool) -> Colour:
    """Fill colour of a shape: role colour; fixed neutral (80, 80, 80); fixed with a role: role colour x 0.5."""
    if not fixed:
        return ROLE_COLOURS[role]
    return FIXED_NEUTRAL if role == NEUTRAL else scaled(ROLE_COLOURS[role], FIXED_ROLE_SCALE)


def outline(fill: Colour) -> Colour:
    return scaled(fill, 0.45)


def motor_colour(binding: int, auto: bool) -> Colour:
    """Ring colour of a motorised revolute joint: per binding 0..3, or the auto colour."""
    return AUTO_MOTOR_COLOUR if auto else MOTOR_COLOURS[binding % NUM_MOTOR_BINDINGS]


def _motor_label(binding: int, auto: bool) -> str:
    return "A" if auto else f"M{binding}"


# --- scene data ----------------------------------------------------------------------------------
def rotate(v: np.ndarray, angle: float) -> np.ndarray:
    """Rotate (..., 2) vectors counter-clockwise by `angle` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _host(tree) -> dict[str, np.ndarray]:
    """A flax dataclass's fields as numpy arrays."""
    return {name: np.asarray(getattr(tree, name)) for name in tree.__dataclass_fields__}


def _actions(actions) -> np.ndarray | None:
    """The 6 binding actions (4 motor in [-1, 1], 2 thruster in [0, 1]) as float64, or None."""
    if actions is None:
        return None
    values = np.asarray(actions, dtype=np.float64).reshape(-1)
    if values.shape != (ACTION_WIDTH,):
        raise ValueError(f"actions: need {ACTION_WIDTH} values, got {values.shape}")
    return values


def _body_point(bodies: dict[str, np.ndarray], slot: int, local: np.ndarray) -> np.ndarray:
    """World point [m] of a point given in the body frame of `slot` [m]."""
    return bodies["position"][slot].astype(np.float64) + rotate(local.astype(np.float64), float(bodies["angle"][slot]))


def _box(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    """Corners (4, 2) [m] of the axis-aligned box [x0, x1] x [y0, y1]."""
    return np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], dtype=np.float64)


def _walls(bodies: dict[str, np.ndarray]) -> list[Wall]:
    """Active walls and the ceiling: light strips with a dark inner face, in their role colour when they have one."""
    (x_lo, x_hi), (y_lo, y_hi) = VIEW_X, VIEW_Y
    strips = (
        (1, _box(x_lo, y_lo, ARENA_LEFT, y_hi), ((ARENA_LEFT, y_lo), (ARENA_LEFT, ARENA_TOP))),
        (2, _box(ARENA_RIGHT, y_lo, x_hi, y_hi), ((ARENA_RIGHT, y_lo), (ARENA_RIGHT, ARENA_TOP))),
        (3, _box(x_lo, ARENA_TOP, x_hi, y_hi), ((x_lo, ARENA_TOP), (x_hi, ARENA_TOP))),
    )
    walls = []
    for slot, strip, face in strips:
        if not bodies["active"][slot]:
            continue
        role = int(bodies["role"][slot])
        fill = WALL_FILL if role == NEUTRAL else mix(ROLE_COLOURS[role], BACKGROUND, 0.3)
        line = WALL_LINE if role == NEUTRAL else outline(ROLE_COLOURS[role])
        walls.append(Wall(slot, strip, np.asarray(face, dtype=np.float64), fill, line))
    return walls


def _shape(bodies: dict[str, np.ndarray], slot: int, fill: Colour) -> Shape:
    n = int(bodies["num_vertices"][slot])
    if n > 0:
        return Shape(slot, fill, outline(fill), points=_body_point(bodies, slot, bodies["vertices"][slot, :n]))
    centre = bodies["position"][slot].astype(np.float64)
    return Shape(
        slot,
        fill,
        outline(fill),
        centre=centre,
        radius=float(bodies["radius"][slot]),
        angle=float(bodies["angle"][slot]),
    )


def _shapes(bodies: dict[str, np.ndarray]) -> list[Shape]:
    """The floor (slot 0, in its role colour or the fixed colour), then every active shape past the arena:
    fixed ones first, so movable shapes show on top of them."""
    shapes = []
    if bodies["active"][0]:
        role = int(bodies["role"][0])
        shapes.append(_shape(bodies, 0, FIXED_NEUTRAL if role == NEUTRAL else ROLE_COLOURS[role]))
    slots = [s for s in range(NUM_ARENA_POLYGONS, len(bodies["active"])) if bodies["active"][s]]
    for slot in sorted(slots, key=lambda s: not bodies["fixed"][s]):
        shapes.append(_shape(bodies, slot, body_fill(int(bodies["role"][slot]), bool(bodies["fixed"][slot]))))
    return shapes


def joint_anchor(bodies: dict[str, np.ndarray], joints: dict[str, np.ndarray], j: int) -> np.ndarray:
    """World anchor [m] of joint `j`: position[body_a] + rotate(anchor_a, angle[body_a])."""
    return _body_point(bodies, int(joints["body_a"][j]), joints["anchor_a"][j])


def _joints(bodies, joints, bindings, actions) -> list[Joint]:
    out = []
    for j in np.flatnonzero(joints["active"]):
        anchor = joint_anchor(bodies, joints, j)
        if joints["fixed"][j] or not joints["motor_on"][j]:
            out.append(Joint(int(j), anchor, bool(joints["fixed"][j])))
            continue
        binding, auto = int(bindings["motor"][j]), bool(bindings["motor_auto"][j])
        action = (
            None if actions is None else 1.0 if auto else float(np.clip(actions[binding % NUM_MOTOR_BINDINGS], -1, 1))
        )
        out.append(Joint(int(j), anchor, False, motor_colour(binding, auto), action, _motor_label(binding, auto)))
    return out


def _thrusters(bodies, thrusters, bindings, actions) -> list[Thruster]:
    """Every active thruster on an active body."""
    out = []
    for t in np.flatnonzero(thrusters["active"]):
        slot = int(thrusters["body"][t])
        if not bodies["active"][slot]:
            continue
        binding = int(bindings["thruster"][t]) % NUM_THRUSTER_BINDINGS
        action = None if actions is None else float(np.clip(actions[NUM_MOTOR_BINDINGS + binding], 0, 1))
        anchor = _body_point(bodies, slot, thrusters["anchor"][t])
        push = float(bodies["angle"][slot]) + float(thrusters["angle"][t])
        out.append(Thruster(int(t), anchor, push, THRUSTER_COLOURS[binding], action, f"T{binding}"))
    return out


def _legend(joints, bindings, thrusters, actions) -> list[tuple[str, Colour]]:
    """(text, colour) per binding used by an active actuator, motors first; with the action when given."""
    motors: dict[str, Colour] = {}
    for j in np.flatnonzero(joints["active"] & joints["motor_on"] & ~joints["fixed"]):
        binding, auto = int(bindings["motor"][j]), bool(bindings["motor_auto"][j])
        motors[_motor_label(binding, auto)] = motor_colour(binding, auto)
    entries = []
    for key in sorted(motors, key=lambda k: (k == "A", k)):
        text = key
        if actions is not None and key != "A":
            text = f"{key} {actions[int(key[1])]:+.1f}"
        entries.append((text, motors[key]))
    used = sorted({int(b) % NUM_THRUSTER_BINDINGS for b in bindings["thruster"][thrusters["active"]]})
    for binding in used:
        text = f"T{binding}" if actions is None else f"T{binding} {actions[NUM_MOTOR_BINDINGS + binding]:.1f}"
        entries.append((text, THRUSTER_COLOURS[binding]))
    return entries


def describe_scene(physics, bindings, actions=None) -> Scene:
    """What a picture of one scene shows.

    Args:
        physics: engine `State` of one scene (numpy or jax leaves, no batch axis).
        bindings: `kinetix_cli.env.level.Bindings` of the same scene.
        actions: the 6 binding actions (4 motor in [-1, 1], 2 thruster in [0, 1]), or None.
    """
    bodies, joints, thrusters = _host(physics.bodies), _host(physics.joints), _host(physics.thrusters)
    if bodies["position"].ndim != 2:
        raise ValueError(f"one scene only: body positions must be (N, 2), got {bodies['position'].shape}")
    binds = _host(bindings)
    acts = _actions(actions)
    return Scene(
        walls=_walls(bodies),
        shapes=_shapes(bodies),
        joints=_joints(bodies, joints, binds, acts),
        thrusters=_thrusters(bodies, thrusters, binds, acts),
        legend=_legend(joints, binds, thrusters, acts),
    )


def scene_json(scene: Scene) -> dict:
    """The scene as JSON-ready lists and numbers (rounded to 0.1 mm: for drawing, not for physics)."""

    def value(v):
        if isinstance(v, np.ndarray):
            return np.round(v, 4).tolist()
        if isinstance(v, float):
            return round(v, 4)
        return list(v) if isinstance(v, tuple) else v

    def entry(item) -> dict:
        return {
            f.name: value(getattr(item, f.name)) for f in dataclasses.fields(item) if getattr(item, f.name) is not None
        }

    return {
        "walls": [entry(w) for w in scene.walls],
        "shapes": [entry(s) for s in scene.shapes],
        "joints": [entry(j) for j in scene.joints],
        "thrusters": [entry(t) for t in scene.thrusters],
        "legend": [[text, list(colour)] for text, colour in scene.legend],
    }
