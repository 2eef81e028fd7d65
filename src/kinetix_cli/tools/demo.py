"""`kinetix demo`: a car drives up a ramp. A small, real end-to-end run of the engine on the CPU."""

from __future__ import annotations

import dataclasses
import math
import time

import jax
import jax.numpy as jnp
import numpy as np

import engine
from engine import SIZES, BodyRef, Params, Scene, State


@dataclasses.dataclass(frozen=True)
class DemoFrame:
    """The car at one moment: time [s], chassis centre [m], chassis angle [deg], speed [m/s]."""

    t: float
    x: float
    y: float
    angle_deg: float
    speed: float


def car_on_ramp() -> tuple[Scene, BodyRef]:
    """A two-wheeled car (chassis + 2 motorised wheels) left of a fixed ramp. Returns (scene, chassis)."""
    scene = Scene()
    scene.add_polygon((3.6, 0.4), [(-1.0, 0.0), (1.0, 0.0), (1.0, 0.55)], fixed=True, name="ramp")
    chassis = scene.add_box((1.0, 0.85), size=(0.9, 0.2), density=1.0, role=1, name="chassis")
    for x in (0.65, 1.35):
        wheel = scene.add_circle((x, 0.62), radius=0.2, friction=1.0, name=f"wheel at x={x}")
        scene.add_revolute_joint(chassis, wheel, anchor=(x, 0.62), motor_speed=1.0, motor_power=2.0)
    return scene, chassis


def run_demo(seconds: float = 4.0, report_every: float = 0.5) -> tuple[list[DemoFrame], float, float]:
    """Drive the car right (both motors at action -1: clockwise wheels) for `seconds`.

    Returns the frames, the compile time [s] and the simulation speed [engine steps/s].
    """
    static = SIZES["m"]
    params = Params()
    scene, chassis_ref = car_on_ramp()
    chassis = scene.slot(chassis_ref, static)
    state: State = scene.build(static)
    actions = jnp.array([-1.0, -1.0, 0.0, 0.0])
    every = max(1, round(report_every / params.dt))

    @jax.jit
    def advance(state):
        def body(s, _):
            return engine.step(static, params, s, actions)[0], None

        return jax.lax.scan(body, state, None, length=every)[0]

    start = time.perf_counter()
    compiled = advance.lower(state).compile()
    compile_s = time.perf_counter() - start

    def frame(t, s):
        b = jax.device_get(s.bodies)
        return DemoFrame(
            t,
            float(b.position[chassis, 0]),
            float(b.position[chassis, 1]),
            math.degrees(float(b.angle[chassis])),
            float(np.linalg.norm(b.velocity[chassis])),
        )

    frames = [frame(0.0, state)]
    start = time.perf_counter()
    for i in range(round(seconds / report_every)):
        state = compiled(state)
        frames.append(frame((i + 1) * every * params.dt, state))
    elapsed = time.perf_counter() - start
    return frames, compile_s, len(frames[1:]) * every / elapsed
