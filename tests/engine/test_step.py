"""The step is a recipe of named phases: each runs under a `jax.named_scope`, so profiles and HLO name it."""

from __future__ import annotations

import re

import jax.numpy as jnp

from engine import Params, Scene, Static, step

PHASES = (
    "mass_properties",
    "gravity",
    "motors",
    "thrusters",
    "collide",
    "prepare_contacts",
    "prepare_joints",
    "warm_start",
    "solve_velocities",
    "store_impulses",
    "integrate_positions",
    "correct_joint_positions",
    "clip",
    "touching",
)


def test_every_phase_is_named_in_the_compiled_step():
    static = Static(num_polygons=4, num_circles=1, num_joints=1, num_thrusters=1)  # small: quick to compile
    lowered = step.lower(  # `step` is jitted, `static` static
        static, Params(), Scene().build(static), jnp.zeros(2)
    )
    scopes = set(re.findall(r'op_name="jit\(step\)/([a-z_]+)/', lowered.compile().as_text()))
    assert set(PHASES) <= scopes, f"phases without a named scope: {sorted(set(PHASES) - scopes)}"
