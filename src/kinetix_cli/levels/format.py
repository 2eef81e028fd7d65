"""The vocabulary of the `kinetix-level/1` format that its reader (`parse`) and its writers (`export`, the
reference importer) share, and the JSON layout people read. The format itself: `docs/level-format.md`."""

from __future__ import annotations

import json
from typing import Any

from engine import ARENA_NAMES

ARENA_KEYS = tuple(name.replace(" ", "_") for name in ARENA_NAMES)
"""Keys of the `arena` section and the body names joints use for the arena: floor, left_wall, right_wall,
ceiling (arena slots 0..3)."""
DEFAULT_GRAVITY = (0.0, -9.81)
"""Gravity the format assumes when a level names none [m/s^2]."""


LIMITS: dict[str, tuple[float, float, bool]] = {
    "position": (-15.0, 15.0, False),  # [m]: the engine clips positions to +-15 m (Params.clip_position)
    "anchor": (-15.0, 15.0, False),  # [m]
    "velocity": (-100.0, 100.0, False),  # [m/s]: Params.clip_velocity
    "angular_velocity_deg": (-2865.0, 2865.0, False),  # [deg/s]: 50 rad/s, Params.clip_angular_velocity
    "angle_deg": (-36000.0, 36000.0, False),  # [deg]: 100 turns
    "direction_deg": (-36000.0, 36000.0, False),  # [deg]
    "limits_deg": (-36000.0, 36000.0, False),  # [deg]
    "size": (0.0, 10.0, True),  # [m]: box width and height
    "vertices": (-10.0, 10.0, False),  # [m]: polygon vertices relative to the position
    "radius": (0.0, 5.0, True),  # [m]
    "density": (0.0, 1e4, True),  # [kg/m^2]
    "friction": (0.0, 100.0, False),
    "restitution": (0.0, 1.0, False),
    "gravity": (-1000.0, 1000.0, False),  # [m/s^2]
    "speed": (-100.0, 100.0, False),  # motor speed scale [1]; negative turns the motor the other way
    "power": (0.0, 1e4, False),  # motor or thruster power scale [1]
}
"""(low, high, low excluded) of every number a level file holds, by field; anything outside is an error naming the
range. The bounds keep every value meaningful for the engine and representable in float32."""

PARAM_LIMITS: dict[str, tuple[float, float, bool]] = {
    "dt": (0.0, 0.1, True),  # [s]
    "baumgarte": (0.0, 1.0, False),
    "slop": (0.0, 1.0, False),  # [m]
    "speculative_distance": (0.0, 1.0, False),  # [m]
    "touch_distance": (0.0, 1.0, False),  # [m]
    "restitution_threshold": (0.0, 100.0, False),  # [m/s]
    "friction_scale": (0.0, 10.0, False),
    "joint_velocity_bias": (0.0, 100.0, False),  # [1/s]
    "joint_position_correction": (0.0, 1.0, False),
    "fixed_joint_bias": (0.0, 100.0, False),  # [1/s]
    "limit_bias": (0.0, 100.0, False),  # [1/s]
    "base_motor_speed": (0.0, 1000.0, False),  # [rad/s]
    "base_motor_power": (0.0, 1e6, False),
    "motor_limit_fade": (0.0, 3.15, False),  # [rad]
    "base_thruster_power": (0.0, 1e6, False),  # [N]
    "clip_position": (0.0, 1e4, True),  # [m]
    "clip_velocity": (0.0, 1e4, True),  # [m/s]
    "clip_angular_velocity": (0.0, 1e4, True),  # [rad/s]
}
"""(low, high, low excluded) of every engine constant a level's `params` may set (`engine.Params` fields)."""


def format_level_json(data: Any) -> str:
    """Level JSON as people write it: small objects and lists on one line, the rest two-space indented."""
    return _format(data, 0) + "\n"


def _format(value: Any, depth: int) -> str:
    inline = json.dumps(value)
    if not isinstance(value, dict | list) or (len(inline) + 2 * depth <= 110 and inline.count("{") <= 2):
        return inline
    pad, inner = "  " * depth, "  " * (depth + 1)
    if isinstance(value, list):
        items = [inner + _format(v, depth + 1) for v in value]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    items = [f"{inner}{json.dumps(k)}: {_format(v, depth + 1)}" for k, v in value.items()]
    return "{\n" + ",\n".join(items) + "\n" + pad + "}"


def brief(value: Any, limit: int = 60) -> str:
    """A value as JSON for a message, cut to `limit` characters (a hostile file may hold megabytes)."""
    try:
        text = json.dumps(value)
    except (TypeError, ValueError):  # e.g. an integer too long to print
        text = f"a {type(value).__name__}"
    return text if len(text) <= limit else text[: limit - 3] + "..."
