"""Parse and validate a `kinetix-level/1` JSON value into a `LevelSpec`, which builds into device `Level`s.

The format is documented in `docs/level-format.md`. Parsing is strict: an unknown key, a missing field or a bad
value raises `LevelError` naming the source, the entity and the field. A parsed `LevelSpec` builds into any size
it fits (`LevelSpec.build(static)`); levels of one size share one compile. Reading files (either format) is
`kinetix_cli.levels.files`.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from engine import SIZES, BodyRef, Params, Scene, SceneError, Static
from kinetix_cli.constants import LEVEL_FORMAT, NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS, ROLE_NAMES
from kinetix_cli.env.level import Bindings, Level, make_level
from kinetix_cli.errors import LevelError
from kinetix_cli.levels.format import ARENA_KEYS, DEFAULT_GRAVITY, LIMITS, PARAM_LIMITS, brief

_TOP_KEYS = {"format", "name", "description", "size", "gravity", "arena", "bodies", "joints", "thrusters", "params"}
_TOP_KEYS |= {"solution"}  # checked by `kinetix_cli.levels.solution.decode_solution` when replayed
_BODY_KEYS = {"name", "shape", "position", "angle_deg", "size", "vertices", "radius", "role", "fixed", "density"}
_BODY_KEYS |= {"friction", "restitution", "collision_mode", "velocity", "angular_velocity_deg"}
_ARENA_BODY_KEYS = {"role", "friction", "restitution", "enabled"}
_JOINT_KEYS = {"name", "type", "a", "b", "anchor", "motor", "limits_deg"}
_MOTOR_KEYS = {"binding", "speed", "power"}
_THRUSTER_KEYS = {"name", "body", "anchor", "direction_deg", "power", "binding"}
_PARAM_KEYS = {f.name for f in dataclasses.fields(Params)}
MAX_NAME = 200
"""Longest level, body, joint or thruster name [characters]."""
MAX_DESCRIPTION = 2000
"""Longest level description [characters]: one line for people."""
AUTO_MOTOR = -1
"""`LevelSpec.motor_bindings` entry of an auto motor (always +1)."""


@dataclasses.dataclass
class LevelSpec:
    """A parsed, validated level: the engine scene plus what the environment adds.

    Attributes:
        name: display name.
        description: one-line goal for people.
        size: the size the level was made for ('s', 'm', 'l'), or None for "the smallest that fits".
        scene: the engine scene description (bodies, joints, thrusters, gravity, arena materials).
        motor_bindings: per joint: 0..3 (action binding), `AUTO_MOTOR` (always +1) or None (no motor).
        thruster_bindings: per thruster: 0 or 1.
        params: overrides of engine `Params` fields; they ride in the built level's `engine_params`.
        solution: the level's solution record as written in the file, or None.
        path: the file it came from (for messages), or None.
    """

    name: str
    description: str
    size: str | None
    scene: Scene
    motor_bindings: list[int | None]
    thruster_bindings: list[int]
    params: dict[str, float]
    solution: dict | None = None
    path: str | None = None

    @property
    def source(self) -> str:
        """The file (or, without one, the name) for messages."""
        return self.path or self.name

    def fits(self, static: Static) -> bool:
        """Whether the level's entities fit the capacities of `static`."""
        try:
            self.scene.check_fits(static)
        except SceneError:
            return False
        return True

    def default_size(self) -> str:
        """The level's own size name, or the smallest Kinetix size it fits."""
        if self.size is not None:
            return self.size
        *smaller, largest = SIZES
        for name in smaller:
            if self.fits(SIZES[name]):
                return name
        try:
            self.scene.check_fits(SIZES[largest])
        except SceneError as exc:
            raise LevelError(f"{self.source}: too big for size {largest}, the largest: {exc}") from None
        return largest

    def default_static(self) -> Static:
        """The capacities of `default_size()`."""
        return SIZES[self.default_size()]

    def build(self, static: Static | None = None) -> Level:
        """Build the device level (numpy leaves) at `static` (default: `default_static()`)."""
        static = static or self.default_static()
        try:
            physics = self.scene.build_numpy(static)
        except SceneError as exc:
            raise LevelError(f"{self.source}: {exc}") from None
        motor_binding = np.zeros(static.num_joints, np.int32)
        motor_auto = np.zeros(static.num_joints, bool)
        for j, binding in enumerate(self.motor_bindings):
            motor_auto[j] = binding == AUTO_MOTOR
            motor_binding[j] = max(binding or 0, 0)
        thruster_binding = np.zeros(static.num_thrusters, np.int32)
        thruster_binding[: len(self.thruster_bindings)] = self.thruster_bindings
        return make_level(physics, Bindings(motor_binding, motor_auto, thruster_binding), self.engine_params())

    def engine_params(self) -> Params:
        """The engine's default `Params` with the level's overrides applied."""
        return Params().replace(**self.params)


def parse_level(data: Any, source: str = "<level>") -> LevelSpec:
    """Validate a level's JSON value and build its `LevelSpec`; `source` names it in errors."""
    return _Parser(source).level(data)


class _Parser:
    def __init__(self, source: str) -> None:
        self.source = source
        self.owners: dict[str, str] = {}  # a body's name -> the entity that defined it ("bodies[2]")

    def fail(self, entity: str, field: str, problem: str) -> LevelError:
        return LevelError(f"{self.source}: {entity}: {field}: {problem}")

    # --- typed field readers --------------------------------------------------------------------
    def keys(self, entity: str, obj: Any, allowed: set[str], required: tuple[str, ...] = ()) -> dict:
        if not isinstance(obj, dict):
            raise LevelError(f"{self.source}: {entity}: must be a JSON object, got {type(obj).__name__}")
        unknown = sorted(set(obj) - allowed)
        if unknown:
            raise self.fail(entity, unknown[0], f"unknown key (allowed: {', '.join(sorted(allowed))})")
        for key in required:
            if key not in obj:
                raise self.fail(entity, key, "missing")
        return obj

    def number(self, entity: str, field: str, value: Any, limits: tuple[float, float, bool] | None = None) -> float:
        """A finite number within `limits` (default: the field's in `format.LIMITS`)."""
        low, high, strict_low = limits or LIMITS[field]
        try:
            ok = not isinstance(value, bool) and isinstance(value, int | float) and math.isfinite(value)
        except OverflowError:  # an integer literal beyond any float
            ok = False
        if not ok:
            raise self.fail(entity, field, f"must be a finite number, got {brief(value)}")
        if value < low or value > high or (strict_low and value == low):
            bound = f"> {low:g} and <= {high:g}" if strict_low else f"in [{low:g}, {high:g}]"
            raise self.fail(entity, field, f"must be {bound}, got {brief(value)}")
        return float(value)

    def vector(self, entity: str, field: str, value: Any) -> tuple[float, float]:
        if not isinstance(value, list) or len(value) != 2:
            raise self.fail(entity, field, f"must be [x, y], got {brief(value)}")
        return (self.number(entity, field, value[0]), self.number(entity, field, value[1]))

    def boolean(self, entity: str, field: str, value: Any) -> bool:
        if not isinstance(value, bool):
            raise self.fail(entity, field, f"must be true or false, got {brief(value)}")
        return value

    def string(self, entity: str, field: str, value: Any) -> str:
        if not isinstance(value, str) or not value:
            raise self.fail(entity, field, f"must be a non-empty string, got {brief(value)}")
        if len(value) > MAX_NAME:
            raise self.fail(entity, field, f"at most {MAX_NAME} characters, got {len(value):,}")
        return value

    def choice(self, entity: str, field: str, value: Any, choices: tuple) -> Any:
        if value not in choices or isinstance(value, bool):
            options = ", ".join(json.dumps(c) for c in choices)
            raise self.fail(entity, field, f"must be one of {options}, got {brief(value)}")
        return value

    def items(self, field: str, value: Any) -> list:
        if not isinstance(value, list):
            raise self.fail("level", field, f"must be a list, got {type(value).__name__}")
        return value

    # --- sections -------------------------------------------------------------------------------
    def level(self, data: Any) -> LevelSpec:
        if isinstance(data, dict) and "format" in data and data["format"] != LEVEL_FORMAT:  # the version first
            raise self.fail(
                "level", "format", f"this kinetix reads {json.dumps(LEVEL_FORMAT)} only, got {brief(data['format'])}"
            )
        data = self.keys("level", data, _TOP_KEYS, required=("format", "bodies"))
        name = self.string("level", "name", data.get("name", Path(self.source).stem[:MAX_NAME]))
        description = data.get("description", "")
        if not isinstance(description, str):
            raise self.fail("level", "description", "must be a string")
        if len(description) > MAX_DESCRIPTION:
            raise self.fail("level", "description", f"at most {MAX_DESCRIPTION} characters, got {len(description):,}")
        size = data.get("size")
        if size is not None:
            self.choice("level", "size", size, tuple(SIZES))
        scene = Scene(gravity=self.vector("level", "gravity", data.get("gravity", list(DEFAULT_GRAVITY))))
        self.arena(scene, data.get("arena", {}))
        refs: dict[str, BodyRef] = {key: BodyRef("arena", i) for i, key in enumerate(ARENA_KEYS)}
        for i, body in enumerate(self.items("bodies", data["bodies"])):
            self.body(scene, refs, f"bodies[{i}]", body)
        motor_bindings = [
            self.joint(scene, refs, f"joints[{i}]", joint)
            for i, joint in enumerate(self.items("joints", data.get("joints", [])))
        ]
        thruster_bindings = [
            self.thruster(scene, refs, f"thrusters[{i}]", thruster)
            for i, thruster in enumerate(self.items("thrusters", data.get("thrusters", [])))
        ]
        params = self.params(data.get("params", {}))
        solution = data.get("solution")
        if solution is not None and not isinstance(solution, dict):
            raise self.fail("level", "solution", "must be a JSON object")
        spec = LevelSpec(name, description, size, scene, motor_bindings, thruster_bindings, params, solution)
        spec.path = self.source
        if size is not None and not spec.fits(SIZES[size]):
            try:
                scene.check_fits(SIZES[size])
            except SceneError as exc:
                raise self.fail(
                    "level", "size", f"too big for size {size}: {str(exc).removeprefix('scene: ')}"
                ) from None
        spec.build(spec.default_static())  # the remaining checks (geometry, references) run here
        return spec

    def arena(self, scene: Scene, arena: Any) -> None:
        arena = self.keys("arena", arena, set(ARENA_KEYS))
        for i, key in enumerate(ARENA_KEYS):
            entity = f"arena.{key}"
            spec = self.keys(entity, arena.get(key, {}), _ARENA_BODY_KEYS)
            body = scene.arena[i]
            body.role = ROLE_NAMES.index(self.choice(entity, "role", spec.get("role", "neutral"), ROLE_NAMES))
            body.friction = self.number(entity, "friction", spec.get("friction", 1.0))
            body.restitution = self.number(entity, "restitution", spec.get("restitution", 0.0))
            body.active = self.boolean(entity, "enabled", spec.get("enabled", True))

    @staticmethod
    def named(entity: str, obj: Any) -> str:
        """`entity` with the object's name, when it has a usable one, for messages."""
        name = obj.get("name") if isinstance(obj, dict) else None
        return f"{entity} '{name}'" if isinstance(name, str) and name else entity

    def body(self, scene: Scene, refs: dict, entity: str, body: Any) -> None:
        entity = self.named(entity, body)
        body = self.keys(entity, body, _BODY_KEYS, required=("name", "shape", "position"))
        name = self.string(entity, "name", body["name"])
        if name in refs:
            other = f"the arena's {name}" if refs[name].kind == "arena" else self.owners[name]
            raise self.fail(entity, "name", f"already used by {other} (body names are unique, not an arena name)")
        shape = self.choice(entity, "shape", body["shape"], ("box", "polygon", "circle"))
        position = self.vector(entity, "position", body["position"])
        material = {
            "role": ROLE_NAMES.index(self.choice(entity, "role", body.get("role", "neutral"), ROLE_NAMES)),
            "fixed": self.boolean(entity, "fixed", body.get("fixed", False)),
            "density": self.number(entity, "density", body.get("density", 1.0)),
            "friction": self.number(entity, "friction", body.get("friction", 1.0)),
            "restitution": self.number(entity, "restitution", body.get("restitution", 0.0)),
            "collision_mode": self.choice(entity, "collision_mode", body.get("collision_mode", 1), (0, 1, 2)),
            "velocity": self.vector(entity, "velocity", body.get("velocity", [0.0, 0.0])),
            "angular_velocity": math.radians(
                self.number(entity, "angular_velocity_deg", body.get("angular_velocity_deg", 0.0))
            ),
        }
        angle = math.radians(self.number(entity, "angle_deg", body.get("angle_deg", 0.0)))
        needs = {"box": "size", "polygon": "vertices", "circle": "radius"}[shape]
        for other in {"size", "vertices", "radius"} - {needs}:
            if other in body:
                raise self.fail(entity, other, f"not used by shape {json.dumps(shape)} (it takes {needs})")
        if needs not in body:
            raise self.fail(entity, needs, f"missing (shape {json.dumps(shape)} needs it)")
        if shape == "box":
            w, h = self.vector(entity, "size", body["size"])
            if w <= 0 or h <= 0:
                raise self.fail(entity, "size", f"width and height must be > 0, got {brief(body['size'])}")
            ref = scene.add_box(position, (w, h), angle, name=name, **material)
        elif shape == "polygon":
            vertices = body["vertices"]
            if not isinstance(vertices, list) or not 3 <= len(vertices) <= 4:
                raise self.fail(entity, "vertices", "must be a list of 3 or 4 [x, y] points")
            points = [self.vector(entity, "vertices", v) for v in vertices]
            ref = scene.add_polygon(position, points, angle, name=name, **material)
        else:
            radius = self.number(entity, "radius", body["radius"])
            ref = scene.add_circle(position, radius, name=name, angle=angle, **material)
        refs[name] = ref
        self.owners[name] = entity.partition(" ")[0]

    def body_ref(self, refs: dict, entity: str, field: str, value: Any) -> BodyRef:
        name = self.string(entity, field, value)
        if name not in refs:
            raise self.fail(entity, field, f"no body named {brief(name)}")
        return refs[name]

    def joint(self, scene: Scene, refs: dict, entity: str, joint: Any) -> int | None:
        entity = self.named(entity, joint)
        joint = self.keys(entity, joint, _JOINT_KEYS, required=("a", "b", "anchor"))
        name = self.string(entity, "name", joint.get("name", entity))
        kind = self.choice(entity, "type", joint.get("type", "revolute"), ("revolute", "fixed"))
        a = self.body_ref(refs, entity, "a", joint["a"])
        b = self.body_ref(refs, entity, "b", joint["b"])
        if a == b:
            raise self.fail(entity, "b", "a joint needs two different bodies")
        anchor = self.vector(entity, "anchor", joint["anchor"])
        if kind == "fixed":
            for field in ("motor", "limits_deg"):
                if field in joint:
                    raise self.fail(entity, field, "a fixed joint has no motor or limits")
            scene.add_fixed_joint(a, b, anchor, name=name)
            return None
        limits = None
        if "limits_deg" in joint:
            lo, hi = self.vector(entity, "limits_deg", joint["limits_deg"])
            if lo > hi:
                raise self.fail(entity, "limits_deg", f"min {lo} is above max {hi}")
            limits = (math.radians(lo), math.radians(hi))
        binding, speed, power = None, None, 1.0
        if "motor" in joint:
            motor = self.keys(f"{entity}.motor", joint["motor"], _MOTOR_KEYS, required=("binding",))
            bindings = (*range(NUM_MOTOR_BINDINGS), "auto")
            binding = self.choice(f"{entity}.motor", "binding", motor["binding"], bindings)
            binding = AUTO_MOTOR if binding == "auto" else binding
            speed = self.number(f"{entity}.motor", "speed", motor.get("speed", 1.0))
            power = self.number(f"{entity}.motor", "power", motor.get("power", 1.0))
        scene.add_revolute_joint(a, b, anchor, motor_speed=speed, motor_power=power, limits=limits, name=name)
        return binding

    def thruster(self, scene: Scene, refs: dict, entity: str, thruster: Any) -> int:
        entity = self.named(entity, thruster)
        thruster = self.keys(entity, thruster, _THRUSTER_KEYS, required=("body", "direction_deg"))
        name = self.string(entity, "name", thruster.get("name", entity))
        ref = self.body_ref(refs, entity, "body", thruster["body"])
        if ref.kind == "arena":
            raise self.fail(entity, "body", "a thruster on the arena cannot move anything")
        body = scene.body(ref)
        anchor = self.vector(entity, "anchor", thruster.get("anchor", list(body.position)))
        angle = math.radians(self.number(entity, "direction_deg", thruster["direction_deg"]))
        power = self.number(entity, "power", thruster.get("power", 1.0))
        binding = self.choice(entity, "binding", thruster.get("binding", 0), tuple(range(NUM_THRUSTER_BINDINGS)))
        scene.add_thruster(ref, anchor, angle, power, name=name)
        return binding

    def params(self, params: Any) -> dict[str, float]:
        params = self.keys("params", params, _PARAM_KEYS)
        return {key: self.number("params", key, value, PARAM_LIMITS[key]) for key, value in params.items()}
