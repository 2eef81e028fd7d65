"""Host-side scene builder: describe bodies, joints and thrusters in plain Python, build device `State`.

Positions, anchors and angles are given in world coordinates [m, rad] at build time. Every invalid
description raises `SceneError` naming the entity and the field.

Examples:
    A green car body on a motorised wheel, built at size m (6 polygon slots, the first 4 the arena's, then 3
    circle slots):

    >>> from engine import SIZES
    >>> scene = Scene()
    >>> car = scene.add_box((1.0, 1.0), size=(1.0, 0.3), role=1)
    >>> wheel = scene.add_circle((0.7, 0.7), radius=0.2)
    >>> scene.add_revolute_joint(car, wheel, anchor=(0.7, 0.7), motor_speed=1.0, motor_power=1.0)
    0
    >>> state = scene.build(SIZES["m"])
    >>> state.bodies.position.shape
    (9, 2)
    >>> scene.slot(car, SIZES["m"]), scene.slot(wheel, SIZES["m"])
    (4, 6)

    A description is checked when it is built:

    >>> scene.add_circle((4.0, 1.0), radius=0.2, role=5)
    BodyRef(kind='circle', index=1)
    >>> scene.build(SIZES["m"])
    Traceback (most recent call last):
    ...
    engine.scene.SceneError: circle 'circle 1': role: must be 0 (neutral), 1 (green), 2 (blue) or 3 (red), got 5
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import jax
import jax.numpy as jnp
import numpy as np

from engine.config import NUM_ARENA_POLYGONS, Static
from engine.geometry import polygon_area_centroid, rotate
from engine.pairs import pair_table
from engine.state import Bodies, ContactCache, Joints, State, Thrusters

ARENA_NAMES = ("floor", "left wall", "right wall", "ceiling")
ARENA_LEFT, ARENA_RIGHT = 0.0, 5.0
"""World x of the inner faces of the left and right walls [m]."""
FLOOR_TOP, ARENA_TOP = 0.4, 5.0
"""World y of the floor's top face and of the ceiling's inner face [m]."""
# (centre, full size) of the static arena boxes around the playable box above.
_ARENA_BOXES = (
    ((2.5, -4.8), (15.0, 10.4)),
    ((-2.5, 5.0), (5.0, 10.0)),
    ((7.5, 5.0), (5.0, 10.0)),
    ((2.5, 7.5), (15.0, 5.0)),
)


class SceneError(ValueError):
    """An invalid scene description: the message names the entity and the field."""


@dataclasses.dataclass(frozen=True)
class BodyRef:
    """Handle to a body added to a scene: `kind` is 'polygon', 'circle' or 'arena', `index` counts within it."""

    kind: str
    index: int


@dataclasses.dataclass
class Body:
    """A body description. `vertices` are relative to `position` before rotation by `angle` (polygons)."""

    name: str
    kind: str
    position: tuple
    angle: float = 0.0
    vertices: np.ndarray | None = None
    radius: float = 0.0
    density: float = 1.0
    friction: float = 1.0
    restitution: float = 0.0
    collision_mode: int = 1
    role: int = 0
    fixed: bool = False
    active: bool = True
    velocity: tuple = (0.0, 0.0)
    angular_velocity: float = 0.0


@dataclasses.dataclass
class Joint:
    """A joint description: `anchor` is the world point where the bodies are pinned."""

    name: str
    body_a: BodyRef
    body_b: BodyRef
    anchor: tuple
    fixed: bool = False
    motor_on: bool = False
    motor_speed: float = 1.0
    motor_power: float = 1.0
    limits: tuple | None = None
    ref_angle: float | None = None


@dataclasses.dataclass
class Thruster:
    """A thruster description: world `anchor`, world `angle` of the push [rad], `power` scale."""

    name: str
    body: BodyRef
    anchor: tuple
    angle: float
    power: float = 1.0


def _err(entity: str, field: str, problem: str) -> SceneError:
    return SceneError(f"{entity}: {field}: {problem}")


def _finite(entity: str, field: str, value) -> np.ndarray:
    arr = np.asarray(value, dtype=np.float64)
    if not np.all(np.isfinite(arr)):
        raise _err(entity, field, f"must be finite, got {value!r}")
    return arr


def _vector(entity: str, field: str, value) -> np.ndarray:
    arr = _finite(entity, field, value)
    if arr.shape != (2,):
        raise _err(entity, field, f"must be an (x, y) pair, got {value!r}")
    return arr


def normalise_polygon(entity: str, vertices) -> tuple[np.ndarray, np.ndarray]:
    """Validate 3-4 convex vertices of either winding; return (counter-clockwise vertices about the area
    centroid (n, 2), centroid (2,)) in the input frame. Raises SceneError for degenerate or non-convex input."""
    v = _finite(entity, "vertices", vertices)
    if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] not in (3, 4):
        raise _err(entity, "vertices", f"need 3 or 4 (x, y) vertices, got shape {v.shape}")
    padded = np.concatenate([v, v[:1]], 0)[:4] if len(v) == 3 else v
    area, centroid = polygon_area_centroid(padded, np)
    if abs(area) < 1e-6:
        raise _err(entity, "vertices", f"degenerate polygon (area {abs(area):.2e} m^2)")
    if area < 0:
        v = v[::-1].copy()
    edges = np.roll(v, -1, axis=0) - v
    turns = edges[:, 0] * np.roll(edges, -1, axis=0)[:, 1] - edges[:, 1] * np.roll(edges, -1, axis=0)[:, 0]
    lengths = np.linalg.norm(edges, axis=1)
    if np.any(lengths < 1e-4) or np.any(turns <= 1e-9 * max(1.0, float(lengths.max()) ** 2)):
        raise _err(entity, "vertices", "polygon must be strictly convex with distinct vertices")
    return v - centroid, centroid


class Scene:
    """A mutable scene description; `build(static)` turns it into device state."""

    def __init__(self, gravity: Sequence[float] = (0.0, -9.81)) -> None:
        self.gravity = tuple(gravity)
        self.arena: list[Body] = []
        for name, (centre, (w, h)) in zip(ARENA_NAMES, _ARENA_BOXES, strict=True):
            verts = np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])
            # Mode 2, as in the reference: the arena holds even bodies that collide with nothing else (mode 0).
            arena = Body(name=name, kind="polygon", position=centre, vertices=verts, fixed=True, collision_mode=2)
            self.arena.append(arena)
        self.polygons: list[Body] = []
        self.circles: list[Body] = []
        self.joints: list[Joint] = []
        self.thrusters: list[Thruster] = []

    # --- bodies ---------------------------------------------------------------------------------
    def add_polygon(self, position, vertices, angle: float = 0.0, name: str | None = None, **material) -> BodyRef:
        """Add a convex polygon; `vertices` (3 or 4, either winding) are relative to `position`."""
        body = Body(
            name=name or f"polygon {len(self.polygons)}",
            kind="polygon",
            position=tuple(position),
            angle=angle,
            vertices=np.asarray(vertices, dtype=np.float64),
            **material,
        )
        self.polygons.append(body)
        return BodyRef("polygon", len(self.polygons) - 1)

    def add_box(self, position, size, angle: float = 0.0, name: str | None = None, **material) -> BodyRef:
        """Add a rectangle of full `size` (width, height) [m] centred at `position`."""
        w, h = (float(x) / 2 for x in size)
        return self.add_polygon(position, [(-w, -h), (w, -h), (w, h), (-w, h)], angle, name, **material)

    def add_circle(self, position, radius: float, name: str | None = None, angle: float = 0.0, **material) -> BodyRef:
        """Add a circle of `radius` [m] centred at `position`, turned by `angle` [rad] (it matters for
        joint and thruster anchors given in the body frame, and for the drawn spoke)."""
        body = Body(
            name=name or f"circle {len(self.circles)}",
            kind="circle",
            position=tuple(position),
            angle=angle,
            radius=radius,
            **material,
        )
        self.circles.append(body)
        return BodyRef("circle", len(self.circles) - 1)

    def body(self, ref: BodyRef) -> Body:
        """The description behind a handle (raises SceneError when it does not exist)."""
        group = {"polygon": self.polygons, "circle": self.circles, "arena": self.arena}.get(ref.kind)
        if group is None or not 0 <= ref.index < len(group):
            raise SceneError(f"{ref.kind} {ref.index}: does not exist")
        return group[ref.index]

    # --- joints and thrusters -------------------------------------------------------------------
    def add_revolute_joint(
        self,
        a: BodyRef,
        b: BodyRef,
        anchor,
        motor_speed: float | None = None,
        motor_power: float = 1.0,
        limits: tuple[float, float] | None = None,
        name: str | None = None,
    ) -> int:
        """Pin `a` and `b` at the world point `anchor`. A `motor_speed` turns the motor on; `limits` bound
        angle_b - angle_a [rad]. Returns the joint index."""
        self.joints.append(
            Joint(
                name=name or f"joint {len(self.joints)}",
                body_a=a,
                body_b=b,
                anchor=tuple(anchor),
                motor_on=motor_speed is not None,
                motor_speed=1.0 if motor_speed is None else motor_speed,
                motor_power=motor_power,
                limits=limits,
            )
        )
        return len(self.joints) - 1

    def add_fixed_joint(
        self, a: BodyRef, b: BodyRef, anchor, ref_angle: float | None = None, name: str | None = None
    ) -> int:
        """Weld `a` to `b` at `anchor`, holding angle_b - angle_a at `ref_angle` (default: as built)."""
        self.joints.append(
            Joint(
                name=name or f"joint {len(self.joints)}",
                body_a=a,
                body_b=b,
                anchor=tuple(anchor),
                fixed=True,
                ref_angle=ref_angle,
            )
        )
        return len(self.joints) - 1

    def add_thruster(self, body: BodyRef, anchor, angle: float, power: float = 1.0, name: str | None = None) -> int:
        """A thruster on `body` at world point `anchor`, pushing along world `angle` [rad]. Returns its index."""
        self.thrusters.append(
            Thruster(
                name=name or f"thruster {len(self.thrusters)}",
                body=body,
                anchor=tuple(anchor),
                angle=angle,
                power=power,
            )
        )
        return len(self.thrusters) - 1

    # --- build ----------------------------------------------------------------------------------
    def check_fits(self, static: Static) -> None:
        """Raise SceneError when the scene has more entities than `static` holds."""
        counts = (
            ("polygons", len(self.polygons), static.num_polygons - NUM_ARENA_POLYGONS),
            ("circles", len(self.circles), static.num_circles),
            ("joints", len(self.joints), static.num_joints),
            ("thrusters", len(self.thrusters), static.num_thrusters),
        )
        for what, have, room in counts:
            if have > room:
                raise SceneError(f"scene: {what}: has {have} but the size holds {room}")

    def slot(self, ref: BodyRef, static: Static) -> int:
        """Global body slot of a handle for a given size."""
        self.body(ref)
        return static.slot(ref.kind, ref.index)

    def build(self, static: Static) -> State:
        """Validate and build the device state (float32, int32, bool) for size `static`."""
        return jax.tree.map(jnp.asarray, self.build_numpy(static))

    def build_numpy(self, static: Static) -> State:
        """As `build`, with numpy leaves (cheap to stack into batches on the host)."""
        self.check_fits(static)
        _vector("scene", "gravity", self.gravity)
        n = static.num_bodies
        bodies = _empty_bodies(n)
        for kind, kept in (("arena", self.arena), ("polygon", self.polygons), ("circle", self.circles)):
            for i, body in enumerate(kept):
                _fill_body(bodies, static.slot(kind, i), body)

        joints = _empty_joints(static.num_joints)
        for j, joint in enumerate(self.joints):
            self._fill_joint(joints, j, joint, bodies, static)
        thrusters = _empty_thrusters(static.num_thrusters)
        for t, thruster in enumerate(self.thrusters):
            self._fill_thruster(thrusters, t, thruster, bodies, static)

        m = pair_table(static).num_points
        contacts = ContactCache(np.zeros(m, np.float32), np.zeros(m, np.float32), np.full(m, -1, np.int32))
        return State(
            bodies=Bodies(**bodies),
            joints=Joints(**joints),
            thrusters=Thrusters(**thrusters),
            contacts=contacts,
            gravity=np.asarray(self.gravity, np.float32),
        )

    def _ref_slot(self, entity: str, field: str, ref, static: Static) -> int:
        if not isinstance(ref, BodyRef):
            raise _err(entity, field, f"must be a body handle, got {ref!r}")
        try:
            return self.slot(ref, static)
        except SceneError:
            raise _err(entity, field, f"{ref.kind} {ref.index} does not exist") from None

    def _fill_joint(self, joints: dict, j: int, joint: Joint, bodies: dict, static: Static) -> None:
        e = f"joint '{joint.name}'"
        a = self._ref_slot(e, "body_a", joint.body_a, static)
        b = self._ref_slot(e, "body_b", joint.body_b, static)
        if a == b:
            raise _err(e, "body_b", "a joint needs two different bodies")
        anchor = _vector(e, "anchor", joint.anchor)
        for field in ("motor_speed", "motor_power"):
            _finite(e, field, getattr(joint, field))
        if joint.motor_power < 0:
            raise _err(e, "motor_power", f"must be >= 0, got {joint.motor_power}")
        angle_a, angle_b = bodies["angle"][a], bodies["angle"][b]
        joints["body_a"][j], joints["body_b"][j] = a, b
        joints["anchor_a"][j] = rotate(anchor - bodies["position"][a], -angle_a, np)
        joints["anchor_b"][j] = rotate(anchor - bodies["position"][b], -angle_b, np)
        joints["fixed"][j] = joint.fixed
        ref = (angle_b - angle_a) if joint.ref_angle is None else joint.ref_angle
        joints["ref_angle"][j] = _finite(e, "ref_angle", ref)
        joints["motor_on"][j] = joint.motor_on and not joint.fixed
        joints["motor_speed"][j], joints["motor_power"][j] = joint.motor_speed, joint.motor_power
        if joint.limits is not None:
            lo, hi = _vector(e, "limits", joint.limits)
            if lo > hi:
                raise _err(e, "limits", f"min {lo} is above max {hi}")
            joints["has_limits"][j] = True
            joints["min_angle"][j], joints["max_angle"][j] = lo, hi
        joints["active"][j] = True

    def _fill_thruster(self, thrusters: dict, t: int, thruster: Thruster, bodies: dict, static: Static) -> None:
        e = f"thruster '{thruster.name}'"
        slot = self._ref_slot(e, "body", thruster.body, static)
        anchor = _vector(e, "anchor", thruster.anchor)
        angle = float(_finite(e, "angle", thruster.angle))
        if not thruster.power >= 0:
            raise _err(e, "power", f"must be a number >= 0, got {thruster.power!r}")
        body_angle = bodies["angle"][slot]
        thrusters["body"][t] = slot
        thrusters["anchor"][t] = rotate(anchor - bodies["position"][slot], -body_angle, np)
        thrusters["angle"][t] = angle - body_angle
        thrusters["power"][t] = thruster.power
        thrusters["active"][t] = True


def _empty_bodies(n: int) -> dict:
    return {
        "position": np.zeros((n, 2), np.float32),
        "angle": np.zeros(n, np.float32),
        "velocity": np.zeros((n, 2), np.float32),
        "angular_velocity": np.zeros(n, np.float32),
        "vertices": np.zeros((n, 4, 2), np.float32),
        "num_vertices": np.zeros(n, np.int32),
        "radius": np.zeros(n, np.float32),
        "density": np.ones(n, np.float32),
        "friction": np.ones(n, np.float32),
        "restitution": np.zeros(n, np.float32),
        "collision_mode": np.ones(n, np.int32),
        "active": np.zeros(n, bool),
        "fixed": np.zeros(n, bool),
        "role": np.zeros(n, np.int32),
    }


def _empty_joints(j: int) -> dict:
    f = lambda *shape: np.zeros((j, *shape), np.float32)  # noqa: E731
    return {
        "body_a": np.zeros(j, np.int32),
        "body_b": np.zeros(j, np.int32),
        "anchor_a": f(2),
        "anchor_b": f(2),
        "fixed": np.zeros(j, bool),
        "ref_angle": f(),
        "motor_on": np.zeros(j, bool),
        "motor_speed": f(),
        "motor_power": f(),
        "has_limits": np.zeros(j, bool),
        "min_angle": f(),
        "max_angle": f(),
        "active": np.zeros(j, bool),
        "impulse": f(2),
        "angular_impulse": f(),
        "lower_impulse": f(),
        "upper_impulse": f(),
    }


def _empty_thrusters(t: int) -> dict:
    return {
        "body": np.zeros(t, np.int32),
        "anchor": np.zeros((t, 2), np.float32),
        "angle": np.zeros(t, np.float32),
        "power": np.zeros(t, np.float32),
        "active": np.zeros(t, bool),
    }


def _fill_body(bodies: dict, slot: int, body: Body) -> None:
    """Validate one body description and write it into slot `slot` of the body arrays."""
    e = f"{body.kind} '{body.name}'"
    position = _vector(e, "position", body.position)
    angle = float(_finite(e, "angle", body.angle))
    if body.kind == "polygon":
        local, centroid = normalise_polygon(e, body.vertices)
        position = position + rotate(centroid, angle, np)
        padded = np.concatenate([local, local[:1]], 0)[:4]
        bodies["vertices"][slot] = padded
        bodies["num_vertices"][slot] = len(local)
    else:
        radius = float(_finite(e, "radius", body.radius))
        if radius <= 0:
            raise _err(e, "radius", f"must be > 0, got {radius}")
        bodies["radius"][slot] = radius
    for field, low, high in (
        ("density", 0.0, math.inf),
        ("friction", 0.0, math.inf),
        ("restitution", 0.0, 1.0),
    ):
        value = float(_finite(e, field, getattr(body, field)))
        if not (low <= value <= high) or (field == "density" and value <= 0):
            bound = "> 0" if field == "density" else f"in [{low}, {high}]"
            raise _err(e, field, f"must be {bound}, got {value}")
        bodies[field][slot] = value
    if body.collision_mode not in (0, 1, 2):
        raise _err(e, "collision_mode", f"must be 0, 1 or 2, got {body.collision_mode!r}")
    if body.role not in (0, 1, 2, 3):
        raise _err(e, "role", f"must be 0 (neutral), 1 (green), 2 (blue) or 3 (red), got {body.role!r}")
    bodies["position"][slot] = position
    bodies["angle"][slot] = angle
    bodies["velocity"][slot] = _vector(e, "velocity", body.velocity)
    bodies["angular_velocity"][slot] = float(_finite(e, "angular_velocity", body.angular_velocity))
    bodies["collision_mode"][slot] = body.collision_mode
    bodies["role"][slot] = body.role
    bodies["fixed"][slot] = bool(body.fixed)
    bodies["active"][slot] = bool(body.active)


def stack(states: Sequence[State]) -> State:
    """Stack scenes of one size into a batch (leading axis) of device arrays."""
    if not states:
        raise SceneError("stack: need at least one scene")
    return jax.tree.map(lambda *xs: jnp.asarray(np.stack([np.asarray(x) for x in xs])), *states)
