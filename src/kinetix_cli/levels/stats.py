"""What a level set holds: entity, actuator and role counts over its levels (for `kinetix levels info`)."""

from __future__ import annotations

import numpy as np

from engine import NUM_ARENA_POLYGONS, SIZES
from kinetix_cli.constants import RED, ROLE_NAMES
from kinetix_cli.env.level import Level


def _summary(values: np.ndarray) -> dict:
    """mean / min / max of a per-level count."""
    return {"mean": round(float(values.mean()), 3), "min": int(values.min()), "max": int(values.max())}


def level_statistics(size: str, levels: Level) -> dict:
    """Per-level counts summarised over a batch of levels (numpy leaves, leading axis = level)."""
    static = SIZES[size]
    bodies, joints, thrusters = levels.physics.bodies, levels.physics.joints, levels.physics.thrusters
    shapes = bodies.active.copy()
    shapes[:, :NUM_ARENA_POLYGONS] = False
    polygons = shapes[:, : static.num_polygons]
    revolute = joints.active & ~joints.fixed
    motors = revolute & joints.motor_on
    counts = {
        "polygons": polygons.sum(1),
        "circles": shapes[:, static.num_polygons :].sum(1),
        "fixed shapes": (shapes & bodies.fixed).sum(1),
        "revolute joints": revolute.sum(1),
        "fixed joints": (joints.active & joints.fixed).sum(1),
        "motors": motors.sum(1),
        "motors with limits": (motors & joints.has_limits).sum(1),
        "thrusters": thrusters.active.sum(1),
        "red shapes": (shapes & (bodies.role == RED)).sum(1),
    }
    floor = bodies.role[:, 0]
    return {
        "levels": int(bodies.active.shape[0]),
        "per level": {name: _summary(value) for name, value in counts.items()},
        "floor role": {name: int((floor == r).sum()) for r, name in enumerate(ROLE_NAMES)},
        "levels with a motor": int((motors.sum(1) > 0).sum()),
        "levels with a thruster": int((thrusters.active.sum(1) > 0).sum()),
        "levels with red": int(((shapes & (bodies.role == RED)).any(1) | (floor == RED)).sum()),
    }
