"""Levels in the reference Kinetix JSON format (its 74 hand-made levels, KinetixJS editor exports), converted
into `kinetix-level/1`.

A reference file is the reference environment's state, slot by slot: `{"env_state": {"polygon": [...],
"circle": [...], "joint": [...], "thruster": [...], "gravity", "collision_matrix", warm-start caches},
"env_params": {...}, "static_env_params": {...}}`, with vectors written as `{"0": x, "1": y}`. Body slots are
polygons then circles (the first 4 polygons the arena), as in our engine. `convert_reference_level` fills our
engine arrays from it and writes them out with `kinetix_cli.levels.export.export_level`, so the result is an
ordinary level file; it returns, beside it, a `Note` for everything it could not carry over (mapping:
`docs/level-format.md`).

Converted on the way (the physics is unchanged): polygon vertices are turned counter-clockwise and centred on
their centroid (the body's position moves there, anchors follow), revolute limits become absolute
(the reference measures them from the joint's `rotation`), inactive slots are dropped. Dropped without a note
because they change nothing: editor highlights, warm-start caches, the collision matrix when it is the one the
joints imply, rendering settings (screen size, pixels per unit, downscale) and the solver's batch size.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import numpy as np

from engine import NUM_ARENA_POLYGONS, SIZES, Params, Scene, Static, polygon_area_centroid, rotate
from kinetix_cli.constants import NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS, ROLE_NAMES
from kinetix_cli.env.level import empty_bindings, make_level
from kinetix_cli.errors import LevelError
from kinetix_cli.levels.export import export_level
from kinetix_cli.levels.format import brief

_SIZE_OF_COUNTS = {(s.num_polygons, s.num_circles, s.num_joints, s.num_thrusters): k for k, s in SIZES.items()}
# Reference env_params that are our engine `Params` (ours default to the reference's values).
_PARAMS = {
    "dt": "dt",
    "slop": "slop",
    "baumgarte_coefficient_collision": "baumgarte",
    "baumgarte_coefficient_joints_v": "joint_velocity_bias",
    "baumgarte_coefficient_joints_p": "joint_position_correction",
    "baumgarte_coefficient_fjoint_av": "fixed_joint_bias",
    "baumgarte_coefficient_rjoint_limit_av": "limit_bias",
    "clip_position": "clip_position",
    "clip_velocity": "clip_velocity",
    "clip_angular_velocity": "clip_angular_velocity",
    "base_motor_speed": "base_motor_speed",
    "base_motor_power": "base_motor_power",
    "base_thruster_power": "base_thruster_power",
    "motor_joint_limit": "motor_limit_fade",
    "base_friction": "friction_scale",
}
# Reference settings with no place in a level file: (reference default, what to do about a different value).
_UNCARRIED = {
    "env_params": {
        "joint_stiffness": (0.6, "our joint solver has no such factor"),
        "motor_decay_coefficient": (0.1, "our motors use the reference default 0.1"),
        "max_timesteps": (256, "episode length is a run setting: env.max_steps"),
        "dense_reward_scale": (0.1, "reward shaping is a run setting: env.dense_reward_scale"),
        "num_shape_roles": (len(ROLE_NAMES), f"there are {len(ROLE_NAMES)} roles"),
    },
    "static_env_params": {
        "num_solver_iterations": (10, "solver iterations are fixed per size (10)"),
        "frame_skip": (2, "frame skip is a run setting: env.frame_skip"),
        "do_warm_starting": (True, "the engine always warm-starts"),
        "num_motor_bindings": (NUM_MOTOR_BINDINGS, f"there are {NUM_MOTOR_BINDINGS} motor bindings"),
        "num_thruster_bindings": (NUM_THRUSTER_BINDINGS, f"there are {NUM_THRUSTER_BINDINGS} thruster bindings"),
        "max_polygon_vertices": (4, "polygons have at most 4 vertices"),
    },
}
# The reference arena: (position, vertices) of floor, left wall, right wall, ceiling; its inner faces are ours.
_REFERENCE_ARENA = (
    ((2.5, -4.8), ((2.5, 5.2), (2.5, -5.2), (-2.5, -5.2), (-2.5, 5.2))),
    ((0.0, 0.0), ((-5.0, 5.0), (0.0, 5.0), (0.0, 0.0), (-5.0, 0.0))),
    ((0.0, 0.0), ((5.0, 5.0), (10.0, 5.0), (10.0, 0.0), (5.0, 0.0))),
    ((2.5, 10.2), ((2.5, 5.2), (2.5, -5.2), (-2.5, -5.2), (-2.5, 5.2))),
)
_TOL = 1e-4  # [m], [rad] or relative: closer than this counts as equal


@dataclasses.dataclass(frozen=True)
class Note:
    """Something in a reference level that the conversion could not carry over exactly.

    Attributes:
        entity: where it is, e.g. "polygon 5", "joint 2", "env_params".
        field: the reference field, e.g. "inverse_mass".
        message: what differs and what the converted level does instead.
    """

    entity: str
    field: str
    message: str

    def __str__(self) -> str:
        return f"{self.entity}: {self.field}: {self.message}"


def is_reference_level(data: Any) -> bool:
    """Whether a level file's JSON value is in the reference format (it has `env_state`, no `format`)."""
    return isinstance(data, dict) and "env_state" in data and "format" not in data


def convert_reference_level(data: Any, source: str, name: str | None = None) -> tuple[dict, list[Note]]:
    """Convert one reference-format level into a `kinetix-level/1` JSON value.

    Args:
        data: the file's JSON value.
        source: the file, for messages and the description.
        name: the level's display name (default: the file's stem, underscores as spaces).

    Returns:
        The level's JSON value (parse it with `kinetix_cli.levels.parse.parse_level`) and the notes on what was not
        carried over, in file order.

    Raises:
        LevelError: the file is not a well-formed reference level (the message names the file and field).
    """
    return _Converter(source).convert(data, name or Path(source).stem.replace("_", " "))


class _Converter:
    def __init__(self, source: str) -> None:
        self.source = source
        self.notes: list[Note] = []

    # --- reading ------------------------------------------------------------------------------
    def fail(self, where: str, message: str) -> LevelError:
        return LevelError(f"{self.source}: {where}: {message}")

    def note(self, entity: str, field: str, message: str) -> None:
        self.notes.append(Note(entity, field, message))

    def get(self, obj: Any, key: str, where: str) -> Any:
        if not isinstance(obj, dict):
            raise self.fail(where, "must be an object")
        if key not in obj:
            raise self.fail(f"{where}.{key}" if where else key, "missing")
        return obj[key]

    def number(self, obj: dict, key: str, where: str) -> float:
        value = self.get(obj, key, where)
        try:
            ok = not isinstance(value, bool) and isinstance(value, int | float) and math.isfinite(value)
        except OverflowError:  # an integer beyond any float
            ok = False
        if not ok:
            raise self.fail(f"{where}.{key}", f"must be a finite number, got {brief(value)}")
        return float(value)

    def integer(self, obj: dict, key: str, where: str) -> int:
        value = self.get(obj, key, where)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.fail(f"{where}.{key}", f"must be an integer, got {brief(value)}")
        return value

    def flag(self, obj: dict, key: str, where: str) -> bool:
        value = self.get(obj, key, where)
        if not isinstance(value, bool):
            raise self.fail(f"{where}.{key}", f"must be true or false, got {brief(value)}")
        return value

    def vector(self, obj: dict, key: str, where: str, length: int = 2) -> np.ndarray:
        value = self.get(obj, key, where)
        if isinstance(value, list):
            value = {str(i): v for i, v in enumerate(value)}
        if not isinstance(value, dict) or len(value) != length:
            raise self.fail(f"{where}.{key}", f"must be a vector of {length} numbers")
        return np.array([self.number(value, str(i), f"{where}.{key}") for i in range(length)], np.float64)

    def entities(self, state: dict, key: str) -> list[dict]:
        value = self.get(state, key, "env_state")
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            raise self.fail(f"env_state.{key}", "must be a list of objects")
        return value

    # --- converting ---------------------------------------------------------------------------
    def convert(self, data: Any, name: str) -> tuple[dict, list[Note]]:
        if not is_reference_level(data):
            raise self.fail("env_state", "not a reference-format level (no env_state object)")
        state = self.get(data, "env_state", "")
        polygons, circles = self.entities(state, "polygon"), self.entities(state, "circle")
        joints, thrusters = self.entities(state, "joint"), self.entities(state, "thruster")
        if len(polygons) < NUM_ARENA_POLYGONS:
            raise self.fail("env_state.polygon", f"needs the {NUM_ARENA_POLYGONS} arena polygons first")
        shapes = [("polygon", i, p) for i, p in enumerate(polygons)] + [("circle", i, c) for i, c in enumerate(circles)]

        live = [k for k, (_, _, body) in enumerate(shapes) if k >= NUM_ARENA_POLYGONS and self.active(body, k, shapes)]
        static, key = self.size(data, polygons, circles, joints, thrusters, live, shapes)
        slot_of = {k: static.slot("arena", k) for k in range(NUM_ARENA_POLYGONS)}
        placed = {"polygon": 0, "circle": 0}
        for k in live:
            slot_of[k] = static.slot(shapes[k][0], placed[shapes[k][0]])
            placed[shapes[k][0]] += 1

        level = Scene().build_numpy(static)
        arrays = {
            "bodies": {f: np.array(getattr(level.bodies, f)) for f in level.bodies.__dataclass_fields__},
            "joints": {f: np.array(getattr(level.joints, f)) for f in level.joints.__dataclass_fields__},
            "thrusters": {f: np.array(getattr(level.thrusters, f)) for f in level.thrusters.__dataclass_fields__},
        }
        bindings = empty_bindings(static.num_joints, static.num_thrusters)
        offsets = {}  # body slot -> body-frame shift of the centre of mass (anchors move by minus this)
        for k in range(NUM_ARENA_POLYGONS):
            self.arena(arrays["bodies"], k, polygons[k])
        for k in live:
            offsets[slot_of[k]] = self.body(arrays["bodies"], slot_of[k], *shapes[k])
        j_out = 0
        for j, joint in enumerate(joints):
            if self.joint(arrays, bindings, j_out, j, joint, slot_of, offsets):
                j_out += 1
        t_out = 0
        for t, thruster in enumerate(thrusters):
            if self.thruster(arrays, bindings, t_out, t, thruster, slot_of, offsets):
                t_out += 1
        self.collision_matrix(state, shapes, joints)
        gravity = self.vector(state, "gravity", "env_state").astype(np.float32)
        physics = level.replace(
            bodies=level.bodies.replace(**arrays["bodies"]),
            joints=level.joints.replace(**arrays["joints"]),
            thrusters=level.thrusters.replace(**arrays["thrusters"]),
            gravity=gravity,
        )
        level = make_level(physics, bindings, Params().replace(**self.params(data)))
        description = f"Imported from the reference Kinetix level {Path(self.source).name}"
        try:
            out = export_level(level, static, name=name, description=description)
        except ValueError as exc:
            raise self.fail("env_state", str(exc).removeprefix("export_level: ")) from None
        if key is None:
            out.pop("size", None)
        return out, self.notes

    def active(self, body: dict, k: int, shapes: list) -> bool:
        kind, i, _ = shapes[k]
        return self.flag(body, "active", f"env_state.{kind}[{i}]")

    def size(self, data, polygons, circles, joints, thrusters, live, shapes) -> tuple[Static, str | None]:
        """Our size with the file's capacities, else the smallest that holds its active entities."""
        counts = (len(polygons), len(circles), len(joints), len(thrusters))
        if counts in _SIZE_OF_COUNTS:
            key = _SIZE_OF_COUNTS[counts]
            return SIZES[key], key
        used = (
            NUM_ARENA_POLYGONS + sum(shapes[k][0] == "polygon" for k in live),
            sum(shapes[k][0] == "circle" for k in live),
            sum(self.flag(j, "active", f"env_state.joint[{n}]") for n, j in enumerate(joints)),
            sum(self.flag(t, "active", f"env_state.thruster[{n}]") for n, t in enumerate(thrusters)),
        )
        for key, static in SIZES.items():
            capacity = (static.num_polygons, static.num_circles, static.num_joints, static.num_thrusters)
            if all(u <= c for u, c in zip(used, capacity, strict=True)):
                self.note(
                    "static_env_params",
                    "num_polygons/num_circles/num_joints/num_thrusters",
                    f"{'/'.join(map(str, counts))} is not a Kinetix size; the level is written without a size "
                    f"(it loads at size {key}, the smallest that holds it)",
                )
                return static, None
        raise self.fail(
            "env_state",
            f"{used[0]} polygons (arena included), {used[1]} circles, {used[2]} joints and {used[3]} thrusters "
            "are active: too big for size l (12/4/6/2)",
        )

    def arena(self, bodies: dict, k: int, body: dict) -> None:
        where, entity = f"env_state.polygon[{k}]", f"polygon {k} (arena)"
        position = self.vector(body, "position", where)
        n = self.integer(body, "n_vertices", where)
        corners = self.get(body, "vertices", where)
        vertices = [self.vector(corners, str(v), f"{where}.vertices") for v in range(min(max(n, 0), 4))]
        ref_position, ref_vertices = _REFERENCE_ARENA[k]
        same = np.allclose(position, ref_position, atol=1e-3) and n == 4
        same = same and {tuple(np.round(v, 3)) for v in vertices} == {tuple(np.round(v, 3)) for v in ref_vertices}
        if not same or self.number(body, "rotation", where) != 0:
            self.note(entity, "position/vertices", "not the standard arena; imported with the standard arena")
        if self.number(body, "inverse_mass", where) != 0:
            self.note(entity, "inverse_mass", "the arena is always fixed")
        if self.integer(body, "collision_mode", where) != 2:
            self.note(entity, "collision_mode", "the arena always collides with everything (mode 2)")
        bodies["role"][k] = self.role(body, where)
        bodies["friction"][k] = self.number(body, "friction", where)
        bodies["restitution"][k] = self.number(body, "restitution", where)
        bodies["active"][k] = self.flag(body, "active", where)

    def role(self, body: dict, where: str) -> int:
        role = self.integer(body, "role", where)
        if role not in range(len(ROLE_NAMES)):
            choices = ", ".join(f"{i} ({name})" for i, name in enumerate(ROLE_NAMES))
            raise self.fail(f"{where}.role", f"must be one of {choices}, got {role}")
        return role

    def body(self, bodies: dict, slot: int, kind: str, i: int, body: dict) -> np.ndarray:
        """Fill body `slot`; return the body-frame shift of its centre of mass (zero unless re-centred)."""
        where, entity = f"env_state.{kind}[{i}]", f"{kind} {i}"
        angle = self.number(body, "rotation", where)
        position = self.vector(body, "position", where)
        density = self.number(body, "density", where)
        if density <= 0:
            raise self.fail(f"{where}.density", f"must be > 0, got {density}")
        shift = np.zeros(2)
        if kind == "polygon":
            n = self.integer(body, "n_vertices", where)
            if n not in (3, 4):
                raise self.fail(f"{where}.n_vertices", f"must be 3 or 4, got {n}")
            corners = self.get(body, "vertices", where)
            vertices = np.array([self.vector(corners, str(v), f"{where}.vertices") for v in range(n)])
            padded = np.concatenate([vertices, vertices[:1]]) if n == 3 else vertices
            area, centroid = polygon_area_centroid(padded, np)
            if abs(area) < 1e-8:
                raise self.fail(f"{where}.vertices", "the polygon has no area")
            if area < 0:
                vertices = vertices[::-1]
            if np.max(np.abs(centroid)) > 1e-6:
                shift = centroid
                vertices = vertices - centroid
                position = position + rotate(centroid, angle, np)
            bodies["vertices"][slot] = 0.0
            bodies["vertices"][slot, :n] = vertices
            if n == 3:
                bodies["vertices"][slot, 3] = vertices[0]
            bodies["num_vertices"][slot] = n
            mass = density * abs(area)
        else:
            radius = self.number(body, "radius", where)
            if radius <= 0:
                raise self.fail(f"{where}.radius", f"must be > 0, got {radius}")
            bodies["radius"][slot] = radius
            mass = density * math.pi * radius**2
        inverse_mass = self.number(body, "inverse_mass", where)
        fixed = inverse_mass == 0
        if fixed and self.number(body, "inverse_inertia", where) != 0:
            self.note(entity, "inverse_inertia", "a body with infinite mass that can turn; imported fixed")
        if not fixed and abs(1 / inverse_mass - mass) > _TOL * mass:
            self.note(
                entity,
                "inverse_mass",
                f"mass {1 / inverse_mass:.6g} kg is not density x area ({mass:.6g} kg); the format derives mass "
                "from density",
            )
        mode = self.integer(body, "collision_mode", where)
        if mode not in (0, 1, 2):
            raise self.fail(f"{where}.collision_mode", f"must be 0, 1 or 2, got {mode}")
        bodies["position"][slot] = position
        bodies["angle"][slot] = angle
        bodies["velocity"][slot] = self.vector(body, "velocity", where)
        bodies["angular_velocity"][slot] = self.number(body, "angular_velocity", where)
        bodies["density"][slot] = density
        bodies["friction"][slot] = self.number(body, "friction", where)
        bodies["restitution"][slot] = self.number(body, "restitution", where)
        bodies["collision_mode"][slot] = mode
        bodies["fixed"][slot] = fixed
        bodies["role"][slot] = self.role(body, where)
        bodies["active"][slot] = True
        return shift

    def endpoint(self, index: int, field: str, entity: str, slot_of: dict) -> int | None:
        if index in slot_of:
            return slot_of[index]
        self.note(entity, field, f"body {index} is missing or inactive; the {entity.split()[0]} is dropped")
        return None

    def joint(self, arrays, bindings, j: int, n: int, joint: dict, slot_of, offsets) -> bool:
        """Fill joint slot `j` from reference joint `n`; False if it is inactive or dropped."""
        where, entity = f"env_state.joint[{n}]", f"joint {n}"
        if not self.flag(joint, "active", where):
            return False
        a = self.endpoint(self.integer(joint, "a_index", where), "a_index", entity, slot_of)
        b = self.endpoint(self.integer(joint, "b_index", where), "b_index", entity, slot_of)
        if a is None or b is None:
            return False
        if a == b:
            raise self.fail(f"{where}.b_index", "a joint needs two different bodies")
        if j >= len(arrays["joints"]["active"]):
            raise self.fail(where, "more active joints than the size holds")
        bodies, joints = arrays["bodies"], arrays["joints"]
        anchor_a = self.vector(joint, "a_relative_pos", where) - offsets.get(a, 0.0)
        anchor_b = self.vector(joint, "b_relative_pos", where) - offsets.get(b, 0.0)
        world_a = bodies["position"][a] + rotate(anchor_a, bodies["angle"][a], np)
        world_b = bodies["position"][b] + rotate(anchor_b, bodies["angle"][b], np)
        gap = float(np.linalg.norm(world_a - world_b))
        if gap > _TOL:
            self.note(entity, "b_relative_pos", f"the anchors are {gap:.4g} m apart; joined at a's anchor")
            anchor_b = rotate(world_a - bodies["position"][b], -bodies["angle"][b], np)
        rotation = self.number(joint, "rotation", where)
        fixed = self.flag(joint, "is_fixed_joint", where)
        joints["body_a"][j], joints["body_b"][j] = a, b
        joints["anchor_a"][j], joints["anchor_b"][j] = anchor_a, anchor_b
        joints["fixed"][j] = fixed
        joints["active"][j] = True
        built = float(bodies["angle"][b] - bodies["angle"][a])
        if fixed:
            joints["ref_angle"][j] = built
            if abs(rotation - built) > _TOL:
                self.note(entity, "rotation", f"holds {rotation:.4g} rad, built at {built:.4g}; held as built")
            return True
        if self.flag(joint, "motor_has_joint_limits", where):
            lo = self.number(joint, "min_rotation", where) + rotation
            hi = self.number(joint, "max_rotation", where) + rotation
            if lo > hi:
                raise self.fail(f"{where}.min_rotation", "is above max_rotation")
            joints["has_limits"][j] = True
            joints["min_angle"][j], joints["max_angle"][j] = lo, hi
        if self.flag(joint, "motor_on", where):
            speed, power = self.number(joint, "motor_speed", where), self.number(joint, "motor_power", where)
            if speed < 0 or power < 0:
                raise self.fail(f"{where}.motor_speed", f"speed {speed} and power {power} must be >= 0")
            binding = self.integer(joint, "motor_binding", where)
            if binding not in range(NUM_MOTOR_BINDINGS):
                raise self.fail(f"{where}.motor_binding", f"must be 0..{NUM_MOTOR_BINDINGS - 1}, got {binding}")
            joints["motor_on"][j] = True
            joints["motor_speed"][j], joints["motor_power"][j] = speed, power
            bindings.motor[j] = binding
        return True

    def thruster(self, arrays, bindings, t: int, n: int, thruster: dict, slot_of, offsets) -> bool:
        """Fill thruster slot `t` from reference thruster `n`; False if it is inactive or dropped."""
        where, entity = f"env_state.thruster[{n}]", f"thruster {n}"
        if not self.flag(thruster, "active", where):
            return False
        index = self.integer(thruster, "object_index", where)
        if index < NUM_ARENA_POLYGONS:
            self.note(entity, "object_index", "a thruster on the arena pushes nothing; dropped")
            return False
        slot = self.endpoint(index, "object_index", entity, slot_of)
        if slot is None:
            return False
        if t >= len(arrays["thrusters"]["active"]):
            raise self.fail(where, "more active thrusters than the size holds")
        power = self.number(thruster, "power", where)
        if power < 0:
            raise self.fail(f"{where}.power", f"must be >= 0, got {power}")
        binding = self.integer(thruster, "thruster_binding", where)
        if binding not in range(NUM_THRUSTER_BINDINGS):
            raise self.fail(f"{where}.thruster_binding", f"must be 0..{NUM_THRUSTER_BINDINGS - 1}, got {binding}")
        thrusters = arrays["thrusters"]
        thrusters["body"][t] = slot
        thrusters["anchor"][t] = self.vector(thruster, "relative_position", where) - offsets.get(slot, 0.0)
        thrusters["angle"][t] = self.number(thruster, "rotation", where)
        thrusters["power"][t] = power
        thrusters["active"][t] = True
        bindings.thruster[t] = binding
        return True

    def collision_matrix(self, state: dict, shapes: list, joints: list[dict]) -> None:
        """Note pairs whose stored collision flag is not the joints' rule (ours: no collision along joint chains)."""
        matrix = state.get("collision_matrix")
        if matrix is None:
            return
        n = len(shapes)
        linked = np.eye(n, dtype=bool)
        for n_joint, joint in enumerate(joints):
            where = f"env_state.joint[{n_joint}]"
            if self.flag(joint, "active", where):
                a, b = self.integer(joint, "a_index", where), self.integer(joint, "b_index", where)
                if 0 <= a < n and 0 <= b < n:
                    linked[a, b] = linked[b, a] = True
        for _ in range(max(1, math.ceil(math.log2(max(n, 2))))):
            linked = (linked.astype(int) @ linked.astype(int)) > 0
        try:
            stored = np.array([[bool(matrix[str(i)][str(k)]) for k in range(n)] for i in range(n)])
        except (KeyError, TypeError, IndexError):
            raise self.fail("env_state.collision_matrix", f"must be a {n} x {n} table of true/false") from None
        differ = [(i, k) for i, k in zip(*np.nonzero(stored == linked), strict=True) if i < k]
        if differ:
            pairs = ", ".join(f"{i}-{k}" for i, k in differ[:4]) + (" ..." if len(differ) > 4 else "")
            self.note(
                "env_state",
                "collision_matrix",
                f"{len(differ)} pair(s) ({pairs}) differ from the joint rule; our engine uses the joint rule",
            )

    def params(self, data: dict) -> dict[str, float]:
        """Engine `Params` overrides for reference env_params that differ from ours; notes for the rest."""
        env_params = data.get("env_params", {})
        static_params = data.get("static_env_params", {})
        for section, value in (("env_params", env_params), ("static_env_params", static_params)):
            if not isinstance(value, dict):
                raise self.fail(section, f"must be an object, got {brief(value)}")
        defaults = Params()
        overrides = {}
        for ref_key, our_key in _PARAMS.items():
            if ref_key in env_params:
                value = self.number(env_params, ref_key, "env_params")
                default = getattr(defaults, our_key)
                if abs(value - default) > 1e-6 * max(1.0, abs(default)):
                    overrides[our_key] = value
        for section, values in (("env_params", env_params), ("static_env_params", static_params)):
            for key, (default, why) in _UNCARRIED[section].items():
                if key in values and values[key] != default:
                    self.note(section, key, f"{brief(values[key])} is not the default {default!r}; {why}")
        return overrides
