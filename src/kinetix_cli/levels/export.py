"""Write a device `Level` back out as a `kinetix-level/1` JSON value: the inverse of `parse.parse_level`.

Every number is written with the fewest decimals that still load back to the same float32 (angles go out in
degrees, anchors and thruster directions in world space, as the format has them), so generated levels stay
readable. Inactive bodies, joints and thrusters are left out and the remaining ones keep their order, so a
level whose inactive slots are all at the end of each group loads back slot for slot.

What the format cannot hold raises `ValueError` naming the slot and the field: a changed arena geometry, a
fixed joint holding an angle other than the one it is built at, limits or a motor on a fixed
joint, a joint or thruster on a left-out body, a thruster on the arena. What has no effect is dropped without a
word: the binding of a joint without a motor, of an auto motor or of an empty slot, motor speed and power of a
joint without a motor, limit angles of a joint without limits, and the warm-start impulses and contact cache (a
built level starts them at zero). The level's engine constants are written as `params` overrides where they
differ from the engine's defaults. Solutions live outside `Level` and are not written.

Examples:
    A shipped level written back out (`files.save_level(path, data)` writes it; `export_set_level` does the same
    for a level of a generated set): its box comes back as a polygon, its bodies named by slot.

    >>> from kinetix_cli.levels.files import load_level
    >>> from kinetix_cli.levels.suites import suite_folder
    >>> level = load_level(suite_folder("s") / "jet-ball-hop.json").build(SIZES["s"])
    >>> data = export_level(level, SIZES["s"], name="jet ball hop", description="hop over the red wall")
    >>> [body["name"] for body in data["bodies"]]
    ['polygon-0', 'circle-0', 'circle-1']
    >>> data["bodies"][0]  # the file's box "wall"
    {'name': 'polygon-0', 'shape': 'polygon', 'position': [2.6, 0.9],
     'vertices': [[-0.1, -0.5], [0.1, -0.5], [0.1, 0.5], [-0.1, 0.5]], 'role': 'red', 'fixed': True}
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np

from engine import NUM_ARENA_POLYGONS, SIZES, Scene, Static, rotate
from kinetix_cli.constants import LEVEL_FORMAT, NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS, ROLE_NAMES
from kinetix_cli.env.level import Level, default_engine_params
from kinetix_cli.errors import UserError
from kinetix_cli.levels.format import ARENA_KEYS, DEFAULT_GRAVITY
from kinetix_cli.levels.levelset import LevelSet, level_at

_MAX_DECIMALS = 12
_NEAR = 1e-7  # [m] or [rad]: a derived number that no rounding reproduces exactly is written this close
_AT_CENTRE = 1e-6  # [m]: a thruster this close to its body's centre is written without an anchor (the default)
# Arena fields the format fixes (it only sets role, friction, restitution and enabled).
_ARENA_FIXED_FIELDS = (
    "position",
    "angle",
    "velocity",
    "angular_velocity",
    "vertices",
    "num_vertices",
    "radius",
    "density",
    "collision_mode",
    "fixed",
)


def export_level(level: Level, static: Static, *, name: str, description: str) -> dict:
    """The `kinetix-level/1` JSON value of one level; `parse_level` of it builds the same `Level`.

    Args:
        level: one scene (numpy or jax leaves, no batch axis) built at `static`.
        static: the size the level is built at; written as `"size"` when it is one of `engine.SIZES`.
        name: display name of the level (non-empty).
        description: one line for people: what the agent must do.

    Returns:
        A JSON-ready dict (write it with `files.save_level`). Bodies are named "polygon-0",
        "polygon-1", ..., "circle-0", ... in slot order; fields equal to the format's defaults are left out.

    Raises:
        ValueError: the level has a batch axis, does not match `static`, or holds something the format
            cannot express (the message names the slot and the field).
    """
    bodies = _host(level.physics.bodies)
    joints = _host(level.physics.joints)
    thrusters = _host(level.physics.thrusters)
    bindings = _host(level.bindings)
    if not name:
        raise ValueError("export_level: name: must be a non-empty string")
    _check_shapes(bodies, joints, thrusters, static)

    data: dict = {"format": LEVEL_FORMAT, "name": name, "description": description}
    size = next((key for key, s in SIZES.items() if s == static), None)
    if size is not None:
        data["size"] = size
    gravity = np.asarray(level.physics.gravity, np.float32)
    if not np.array_equal(gravity, np.float32(DEFAULT_GRAVITY)):
        data["gravity"] = _f32(gravity)
    arena = _arena(bodies, static)
    if arena:
        data["arena"] = arena

    names = _body_names(bodies, static)
    data["bodies"] = [_body(bodies, slot, body_name, static) for slot, body_name in names.items()]
    exported_joints = [_joint(bodies, joints, bindings, j, names) for j in np.flatnonzero(joints["active"])]
    if exported_joints:
        data["joints"] = exported_joints
    exported_thrusters = [_thruster(bodies, thrusters, bindings, t, names) for t in np.flatnonzero(thrusters["active"])]
    if exported_thrusters:
        data["thrusters"] = exported_thrusters
    params = _params(level)
    if params:
        data["params"] = params
    return data


def export_set_level(levelset: LevelSet, path: Path, index: int) -> dict:
    """Level `index` of the set loaded from `path` as level-file data, named after the set and its index; a level
    the format cannot hold is a `UserError` naming the set and the index."""
    size, seed = levelset.manifest["size"], levelset.manifest["seed"]
    try:
        return export_level(
            level_at(levelset, index),
            SIZES[size],
            name=f"{path.name} {index}",
            description=f"Generated level {index} of {path} (seed {seed}): make green touch blue",
        )
    except ValueError as exc:
        raise UserError(f"{path}: level {index} cannot be written as a level file: {exc}") from None


def _params(level: Level) -> dict[str, float]:
    """The level's engine constants that differ from the defaults, as float32 read-back decimals."""
    defaults = _host(default_engine_params())
    ours = _host(level.engine_params)
    if any(value.ndim for value in ours.values()):
        raise ValueError("export_level: one scene at a time: engine_params has a batch axis")
    return {key: _f32(value) for key, value in ours.items() if np.float32(value) != defaults[key]}


# --- numbers -------------------------------------------------------------------------------------
def _f32(value) -> float | list:
    """A float32 value (or array) as the shortest decimals that read back as the same float32."""
    arr = np.asarray(value, np.float32)
    if arr.ndim == 0:
        return float(str(np.float32(arr))) + 0.0
    return [_f32(v) for v in arr]


def _shortest(value, encode: Callable[[np.ndarray], np.ndarray], target) -> float | list:
    """`value` (float64 scalar or vector) rounded to the fewest decimals whose `encode` (what the parser
    makes of the written number) equals `target` exactly; where no rounding does, the fewest decimals that
    come within `_NEAR` of it; else full precision."""
    value = np.asarray(value, np.float64)
    target = np.asarray(target)
    near = None
    for decimals in range(_MAX_DECIMALS + 1):
        candidate = np.array([round(float(v), decimals) + 0.0 for v in value.reshape(-1)]).reshape(value.shape)
        error = np.max(np.abs(np.asarray(encode(candidate), np.float64) - target))
        if error == 0:
            return candidate.tolist()
        if near is None and error <= _NEAR:
            near = candidate
    return (value + 0.0 if near is None else near).tolist()


def _degrees(radians: np.float32) -> float:
    """An angle stored as float32 radians, in degrees as `math.radians` reads it back."""
    return _shortest(math.degrees(float(radians)), lambda c: np.float32(math.radians(float(c))), np.float32(radians))


def _world_point(bodies: dict, slot: int, local) -> np.ndarray:
    """World point [m] (float64) of a body-frame point `local` of body `slot`."""
    position = bodies["position"][slot].astype(np.float64)
    return position + rotate(np.asarray(local, np.float64), float(bodies["angle"][slot]), np)


def _local(bodies: dict, slot: int, world: np.ndarray) -> np.ndarray:
    """Body-frame point of a world point, computed as `Scene.build` does (float32 result)."""
    return rotate(world - bodies["position"][slot], -bodies["angle"][slot], np).astype(np.float32)


# --- checks --------------------------------------------------------------------------------------
def _host(tree) -> dict[str, np.ndarray]:
    """A flax dataclass's fields as numpy arrays."""
    return {field: np.asarray(getattr(tree, field)) for field in tree.__dataclass_fields__}


def _check_shapes(bodies: dict, joints: dict, thrusters: dict, static: Static) -> None:
    """Raise unless the level is one scene with the slot counts of `static`."""
    if bodies["position"].ndim != 2:
        raise ValueError(
            f"export_level: one scene at a time: body positions are {bodies['position'].shape}, not (N, 2)"
        )
    counts = (
        ("bodies", len(bodies["active"]), static.num_bodies),
        ("joints", len(joints["active"]), static.num_joints),
        ("thrusters", len(thrusters["active"]), static.num_thrusters),
    )
    for what, have, want in counts:
        if have != want:
            raise ValueError(f"export_level: {what}: the level has {have} slots but the size has {want}")


def _arena(bodies: dict, static: Static) -> dict:
    """The `arena` section: each arena body's role, friction, restitution and enabled where not default."""
    default = Scene().build_numpy(static).bodies
    arena = {}
    for i, key in enumerate(ARENA_KEYS):
        for field in _ARENA_FIXED_FIELDS:
            if not np.allclose(bodies[field][i], getattr(default, field)[i], atol=1e-6):
                raise ValueError(f"export_level: arena {key}: {field}: the format cannot change it")
        entry = {}
        if bodies["role"][i] != 0:
            entry["role"] = ROLE_NAMES[int(bodies["role"][i])]
        if bodies["friction"][i] != 1:
            entry["friction"] = _f32(bodies["friction"][i])
        if bodies["restitution"][i] != 0:
            entry["restitution"] = _f32(bodies["restitution"][i])
        if not bodies["active"][i]:
            entry["enabled"] = False
        if entry:
            arena[key] = entry
    return arena


# --- entities ------------------------------------------------------------------------------------
def _body_names(bodies: dict, static: Static) -> dict[int, str]:
    """Slot -> generated name of every active non-arena body, polygons first, in slot order."""
    polygons = [s for s in range(NUM_ARENA_POLYGONS, static.num_polygons) if bodies["active"][s]]
    circles = [s for s in range(static.num_polygons, static.num_bodies) if bodies["active"][s]]
    return {slot: f"polygon-{k}" for k, slot in enumerate(polygons)} | {
        slot: f"circle-{k}" for k, slot in enumerate(circles)
    }


def _body(bodies: dict, slot: int, body_name: str, static: Static) -> dict:
    """One entry of `bodies`: shape, pose and the material fields that differ from the defaults."""
    entry: dict = {"name": body_name}
    angle = bodies["angle"][slot]
    if slot < static.num_polygons:
        n = int(bodies["num_vertices"][slot])
        if n not in (3, 4):
            raise ValueError(f"export_level: {body_name} (slot {slot}): num_vertices: must be 3 or 4, got {n}")
        entry |= {"shape": "polygon", "position": _f32(bodies["position"][slot])}
        entry["vertices"] = [_f32(v) for v in bodies["vertices"][slot][:n]]
    else:
        entry |= {"shape": "circle", "position": _f32(bodies["position"][slot])}
        entry["radius"] = _f32(bodies["radius"][slot])
    if angle != 0:
        entry["angle_deg"] = _degrees(angle)
    if bodies["role"][slot] != 0:
        entry["role"] = ROLE_NAMES[int(bodies["role"][slot])]
    if bodies["fixed"][slot]:
        entry["fixed"] = True
    for field, default in (("density", 1), ("friction", 1), ("restitution", 0)):
        if bodies[field][slot] != default:
            entry[field] = _f32(bodies[field][slot])
    if bodies["collision_mode"][slot] != 1:
        entry["collision_mode"] = int(bodies["collision_mode"][slot])
    if np.any(bodies["velocity"][slot] != 0):
        entry["velocity"] = _f32(bodies["velocity"][slot])
    if bodies["angular_velocity"][slot] != 0:
        entry["angular_velocity_deg"] = _degrees(bodies["angular_velocity"][slot])
    return entry


def _joint(bodies: dict, joints: dict, bindings: dict, j: int, names: dict[int, str]) -> dict:
    """One entry of `joints`: the bodies, the world anchor, and the motor and limits of a revolute joint."""
    entity = f"export_level: joint {j}"
    a, b = int(joints["body_a"][j]), int(joints["body_b"][j])
    for field, slot in (("body_a", a), ("body_b", b)):
        if slot not in names and slot >= NUM_ARENA_POLYGONS:
            raise ValueError(f"{entity}: {field}: body slot {slot} is inactive, so it is not written")
    world_a = _world_point(bodies, a, joints["anchor_a"][j])
    world_b = _world_point(bodies, b, joints["anchor_b"][j])
    if np.max(np.abs(world_a - world_b)) > 1e-5:
        raise ValueError(f"{entity}: anchor_b: at {world_b} in the world, not at anchor_a's {world_a}")
    target = np.concatenate([joints["anchor_a"][j], joints["anchor_b"][j]])
    anchor = _shortest(world_a, lambda c: np.concatenate([_local(bodies, a, c), _local(bodies, b, c)]), target)
    entry: dict = {"a": _body_key(a, names), "b": _body_key(b, names), "anchor": anchor}
    if joints["fixed"][j]:
        built = bodies["angle"][b] - bodies["angle"][a]
        if abs(float(joints["ref_angle"][j] - built)) > 1e-6:
            raise ValueError(f"{entity}: ref_angle: the format holds a fixed joint at the angle it is built at")
        if joints["has_limits"][j] or joints["motor_on"][j]:
            raise ValueError(f"{entity}: the format has no limits or motor on a fixed joint")
        return {"type": "fixed"} | entry
    if joints["motor_on"][j]:
        auto = bool(bindings["motor_auto"][j])
        binding = int(bindings["motor"][j])
        if not auto and binding not in range(NUM_MOTOR_BINDINGS):
            raise ValueError(f"{entity}: motor binding: must be 0..{NUM_MOTOR_BINDINGS - 1}, got {binding}")
        motor: dict = {"binding": "auto" if auto else binding}
        if joints["motor_power"][j] < 0:
            raise ValueError(f"{entity}: motor_power: must be >= 0 in the format, got {joints['motor_power'][j]}")
        for field in ("speed", "power"):
            if (value := joints[f"motor_{field}"][j]) != 1:
                motor[field] = _f32(value)
        entry["motor"] = motor
    if joints["has_limits"][j]:
        entry["limits_deg"] = [_degrees(joints["min_angle"][j]), _degrees(joints["max_angle"][j])]
    return entry


def _thruster(bodies: dict, thrusters: dict, bindings: dict, t: int, names: dict[int, str]) -> dict:
    """One entry of `thrusters`: the body, the world anchor (left out within `_AT_CENTRE` of the body's centre),
    the world direction, and the power and binding where not default."""
    entity = f"export_level: thruster {t}"
    slot = int(thrusters["body"][t])
    if slot < NUM_ARENA_POLYGONS:
        raise ValueError(f"{entity}: body: the format has no thrusters on the arena")
    if slot not in names:
        raise ValueError(f"{entity}: body: body slot {slot} is inactive, so it is not written")
    binding = int(bindings["thruster"][t])
    if binding not in range(NUM_THRUSTER_BINDINGS):
        raise ValueError(f"{entity}: binding: must be 0..{NUM_THRUSTER_BINDINGS - 1}, got {binding}")
    entry: dict = {"body": names[slot]}
    local = thrusters["anchor"][t]
    if np.max(np.abs(local)) > _AT_CENTRE:  # else the default: the body's position, its centre
        world = _world_point(bodies, slot, local)
        entry["anchor"] = _shortest(world, lambda c: _local(bodies, slot, c), local)
    body_angle = bodies["angle"][slot]
    direction = math.degrees(float(body_angle) + float(thrusters["angle"][t]))
    entry["direction_deg"] = _shortest(
        direction, lambda c: np.float32(math.radians(float(c)) - body_angle), thrusters["angle"][t]
    )
    if thrusters["power"][t] != 1:
        entry["power"] = _f32(thrusters["power"][t])
    if binding != 0:
        entry["binding"] = binding
    return entry


def _body_key(slot: int, names: dict[int, str]) -> str:
    """The name a joint uses for body `slot`: an arena key or the generated body name."""
    return ARENA_KEYS[slot] if slot < NUM_ARENA_POLYGONS else names[slot]
