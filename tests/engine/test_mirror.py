"""The mirror image of a scene: stepped with reversed motors it follows the mirror image of the trajectory; mirroring
twice gives the scene back; the arena stays the arena as built."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from engine import SIZES, Scene, mirror_motor_actions, mirror_state, stack
from engine.random_scenes import random_actions, random_scene
from helpers.sim import simulate_batch

STATIC = SIZES["s"]
SWAP_WALLS = np.array([0, 2, 1, *range(3, STATIC.num_bodies)])
"""Slot of each body's mirror image: the left and right walls trade places."""
mirror_states = jax.jit(jax.vmap(mirror_state))  # op by op: ~60 small compiles


def _scenes(seed: int):
    """Four random size-s scenes (the batch other engine tests compile) and random actions."""
    states = stack([random_scene(STATIC, seed * 1000 + i).build_numpy(STATIC) for i in range(4)])
    return states, jnp.asarray(random_actions(STATIC, np.random.default_rng(seed), 4))


@jax.jit
def _mirror_actions(actions):
    j = STATIC.num_joints
    return actions.at[:, :j].set(mirror_motor_actions(actions[:, :j]))


def _trajectory_gap(states, actions, mirrored_actions, chunks: int) -> tuple[float, float]:
    """Largest |x' - (5 - x)|, |y' - y| [m] and |angle' + angle| [rad] over every body and step of `chunks` seconds."""
    _, parts = simulate_batch(STATIC, states, chunks, actions)
    _, mirrored = simulate_batch(STATIC, mirror_states(states), chunks, mirrored_actions)
    position, gap_angle = 0.0, 0.0
    for part, twin in zip(parts, mirrored, strict=True):
        p, q = np.asarray(part[0])[:, :, SWAP_WALLS], np.asarray(twin[0])
        expected = np.stack([5.0 - p[..., 0], p[..., 1]], -1)
        position = max(position, float(np.abs(q - expected).max()))
        gap_angle = max(gap_angle, float(np.abs(np.asarray(twin[1]) + np.asarray(part[1])[:, :, SWAP_WALLS]).max()))
    return position, gap_angle


def test_the_mirror_image_with_reversed_motors_follows_the_mirrored_trajectory():
    """Two seconds of four random scenes (motors, thrusters, contacts, limits): within 2 mm and 2 mrad. The solver's
    sequential contact order is not mirror-symmetric, so this holds to a tolerance, not bit for bit (4.2e-4 m after
    4 s on these scenes)."""
    states, actions = _scenes(seed=4)
    position, angle = _trajectory_gap(states, actions, _mirror_actions(actions), chunks=2)
    assert position < 2e-3 and angle < 2e-3, (position, angle)
    # the check can fail: the same motor actions (not reversed) drive the mirror image elsewhere
    position, angle = _trajectory_gap(states, actions, actions, chunks=2)
    assert position > 0.05, position


def test_mirroring_twice_gives_the_scene_back():
    states, _ = _scenes(seed=5)
    twice = mirror_states(mirror_states(states))
    for path, a, b in zip(
        jax.tree_util.tree_leaves_with_path(states), jax.tree.leaves(states), jax.tree.leaves(twice), strict=True
    ):
        # [m, rad]: x -> 5 - x twice rounds once each way; angles and the rest come back exactly
        np.testing.assert_allclose(np.asarray(b), np.asarray(a), rtol=0, atol=1e-6, err_msg=str(path[0]))


def test_the_arena_stays_as_built_and_a_body_moves_to_the_other_side():
    scene = Scene()
    box = scene.add_polygon(position=(1.0, 1.0), vertices=[(-0.3, -0.1), (0.3, -0.1), (0.3, 0.1), (-0.3, 0.1)])
    scene.add_thruster(box, anchor=(1.0, 1.0), angle=0.3)
    built = scene.build_numpy(STATIC)
    mirrored = mirror_state(built)
    for field in ("position", "angle", "vertices", "active", "role", "friction"):
        np.testing.assert_allclose(  # [m, rad]: the walls' 5 - x rounds in float32
            np.asarray(getattr(mirrored.bodies, field))[:4], getattr(built.bodies, field)[:4], rtol=0, atol=1e-6
        )
    slot = STATIC.slot("polygon", 0)
    np.testing.assert_allclose(np.asarray(mirrored.bodies.position[slot]), [4.0, 1.0], rtol=0, atol=1e-6)  # [m]
    np.testing.assert_allclose(float(mirrored.thrusters.angle[0]), np.pi - 0.3, rtol=0, atol=1e-6)  # [rad]
