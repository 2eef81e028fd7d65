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
