"""Random scenes filled to a size's capacity: shared by the benchmark, the tests and the demo.

Bodies sit on a grid inside the arena (so they start apart), fall, and collide; consecutive bodies are
joined (revolute with motors and limits, or fixed), and thrusters sit on random bodies. Every slot of
the size is used.
"""

from __future__ import annotations

import numpy as np

from engine.config import NUM_ARENA_POLYGONS, Static
from engine.scene import Scene

_COLUMNS = 4
_CELL = 1.05  # grid spacing [m]


def random_scene(static: Static, seed: int) -> Scene:
    """A scene using every polygon, circle, joint and thruster slot of `static`, drawn from `seed`."""
    rng = np.random.default_rng(seed)
    scene = Scene()
    kinds = ["polygon"] * (static.num_polygons - NUM_ARENA_POLYGONS) + ["circle"] * static.num_circles
    rng.shuffle(kinds)
    refs = []
    for i, kind in enumerate(kinds):
        row, col = divmod(i, _COLUMNS)
        centre = (0.85 + col * _CELL + rng.uniform(-0.1, 0.1), 0.95 + row * _CELL + rng.uniform(-0.1, 0.1))
        material = {
            "density": float(rng.uniform(0.5, 2.0)),
            "friction": float(rng.uniform(0.2, 1.0)),
            "restitution": float(rng.choice([0.0, 0.0, 0.3])),
            "role": int(rng.integers(0, 4)),
            "velocity": tuple(rng.uniform(-1.0, 1.0, 2)),
        }
        if kind == "circle":
            refs.append(scene.add_circle(centre, radius=float(rng.uniform(0.1, 0.35)), **material))
        elif rng.uniform() < 0.3:
            r = rng.uniform(0.15, 0.38)
            angles = np.array([0.0, 2.1, 4.2]) + rng.uniform(-0.3, 0.3, 3)
            refs.append(scene.add_polygon(centre, np.stack([r * np.cos(angles), r * np.sin(angles)], 1), **material))
        else:
            size = rng.uniform(0.15, 0.6, 2)
            refs.append(scene.add_box(centre, size=tuple(size), angle=float(rng.uniform(-0.5, 0.5)), **material))

    for j in range(static.num_joints):
        a, b = refs[(2 * j) % len(refs)], refs[(2 * j + 1) % len(refs)]
        pa, pb = np.array(scene.body(a).position), np.array(scene.body(b).position)
        anchor = tuple(0.5 * (pa + pb))
        if rng.uniform() < 0.25:
            scene.add_fixed_joint(a, b, anchor)
        else:
            limits = tuple(sorted(rng.uniform(-np.pi, np.pi, 2))) if rng.uniform() < 0.4 else None
            scene.add_revolute_joint(
                a,
                b,
                anchor,
                motor_speed=float(rng.uniform(0.4, 3.0)),
                motor_power=float(rng.uniform(1.0, 3.0)),
                limits=limits,
            )
    for _ in range(static.num_thrusters):
        ref = refs[int(rng.integers(len(refs)))]
        centre = np.array(scene.body(ref).position)
        scene.add_thruster(
            ref, tuple(centre), angle=float(rng.uniform(0, 2 * np.pi)), power=float(rng.uniform(0.5, 2.0))
        )
    return scene


def random_actions(static: Static, rng: np.random.Generator, batch: int) -> np.ndarray:
    """(batch, J + T) float32 actions: motors in [-1, 1], thrusters in [0, 1]."""
    motors = rng.uniform(-1.0, 1.0, (batch, static.num_joints))
    thrusters = rng.uniform(0.0, 1.0, (batch, static.num_thrusters))
    return np.concatenate([motors, thrusters], axis=1).astype(np.float32)
