"""kinetix engine: a vmappable 2D rigid-body physics engine in JAX.

Typical use::

    from engine import SIZES, Params, Scene, step
    state = scene.build(SIZES["s"])
    state, info = jax.jit(step, static_argnums=0)(SIZES["s"], Params(), state, actions)
"""

from engine.config import SIZES, Params, Static, size
from engine.scene import BodyRef, Scene, SceneError, stack
from engine.state import Bodies, ContactCache, Joints, State, Thrusters
from engine.step import StepInfo, step, step_batch, touching_matrix

__all__ = [
    "SIZES",
    "Bodies",
    "BodyRef",
    "ContactCache",
    "Joints",
    "Params",
    "Scene",
    "SceneError",
    "State",
    "Static",
    "StepInfo",
    "Thrusters",
    "size",
    "stack",
    "step",
    "step_batch",
    "touching_matrix",
]
