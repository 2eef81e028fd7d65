"""kinetix engine: a vmappable 2D rigid-body physics engine in JAX.

Typical use::

    from engine import SIZES, Params, Scene, step
    state = scene.build(SIZES["s"])
    state, info = jax.jit(step, static_argnums=0)(SIZES["s"], Params(), state, actions)

This module is the engine's public API: code outside `src/engine/` imports from `engine` only (an import-linter
contract checks it). Beside the step and its containers it exports the geometry and collision helpers the
environment's observations, the level generator and the importers use.
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
