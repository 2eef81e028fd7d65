"""kinetix engine: a vmappable 2D rigid-body physics engine in JAX.

This module is the engine's public API: code outside `src/engine/` imports from `engine` only (an import-linter
contract checks it). Beside the step and its containers it exports the geometry and collision helpers the
environment's observations, the level generator and the importers use.

Examples:
    A ball dropped from 3 m, stepped for half a second (30 steps of `Params().dt` = 1/60 s); its height [m] and
    vertical velocity [m/s] are free fall's: y = 3 - g dt^2 n (n + 1) / 2, v = -g dt n for n = 30 steps.

    >>> import jax.numpy as jnp
    >>> from engine import SIZES, Params, Scene, step
    >>> static = SIZES["s"]  # capacities; one compile per `Static`
    >>> scene = Scene()
    >>> ball = scene.add_circle((2.5, 3.0), radius=0.2)
    >>> state = scene.build(static)
    >>> actions = jnp.zeros(static.num_actions)  # one per joint (motor), then one per thruster
    >>> for _ in range(30):  # `step` is jitted with `static` static: one compile per `Static`
    ...     state, info = step(static, Params(), state, actions)
    >>> slot = scene.slot(ball, static)  # the ball's row in `state.bodies`
    >>> round(float(state.bodies.position[slot, 1]), 2), round(float(state.bodies.velocity[slot, 1]), 1)
    (1.73, -4.9)
"""

from engine.config import NUM_ARENA_POLYGONS, SIZES, Params, Static, size
from engine.geometry import mass_properties, polygon_area_centroid, rotate
from engine.mirror import mirror_motor_actions, mirror_state
from engine.narrowphase import collide, world_polygons
from engine.pairs import PairTable, collidable_pairs, joint_connectivity, pair_table
from engine.random_scenes import random_actions, random_scene
from engine.scene import ARENA_LEFT, ARENA_NAMES, ARENA_RIGHT, ARENA_TOP, FLOOR_TOP, BodyRef, Scene, SceneError, stack
from engine.state import Bodies, ContactCache, Joints, State, Thrusters
from engine.step import StepInfo, step, step_batch, touching_matrix

__all__ = [
    "ARENA_LEFT",
    "ARENA_NAMES",
    "ARENA_RIGHT",
    "ARENA_TOP",
    "FLOOR_TOP",
    "NUM_ARENA_POLYGONS",
    "SIZES",
    "Bodies",
    "BodyRef",
    "ContactCache",
    "Joints",
    "PairTable",
    "Params",
    "Scene",
    "SceneError",
    "State",
    "Static",
    "StepInfo",
    "Thrusters",
    "collidable_pairs",
    "collide",
    "joint_connectivity",
    "mass_properties",
    "mirror_motor_actions",
    "mirror_state",
    "pair_table",
    "polygon_area_centroid",
    "random_actions",
    "random_scene",
    "rotate",
    "size",
    "stack",
    "step",
    "step_batch",
    "touching_matrix",
    "world_polygons",
]
