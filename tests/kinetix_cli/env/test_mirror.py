"""Mirrored levels, environment states and actions: a mirrored action does in the mirror image what the action does
in the level, auto motors turn the mirror way, mirroring twice gives everything back, and `MirrorPairEnv` observes
the state and its mirror image."""

from __future__ import annotations

import jax
import numpy as np
import pytest

from engine import SIZES
from helpers.levels import CAR
from kinetix_cli.constants import ACTION_TYPES, NUM_MOTOR_BINDINGS
from kinetix_cli.env.actions import binding_values, sample_action
from kinetix_cli.env.environment import KinetixEnv
from kinetix_cli.env.mirror import MirrorPairEnv, mirror_action, mirror_env_state, mirror_level
from kinetix_cli.levels.parse import parse_level

AUTO_CAR = CAR | {"joints": [CAR["joints"][0] | {"motor": {"binding": "auto", "speed": 0.5}}]}


@pytest.mark.parametrize("kind", ACTION_TYPES)
def test_a_mirrored_action_reverses_the_motors_and_keeps_the_thrusters(kind):
    actions = jax.vmap(lambda k: sample_action(kind, k))(jax.random.split(jax.random.key(0), 64))
    values = jax.vmap(lambda a: binding_values(kind, a))(actions)
    mirrored = jax.vmap(lambda a: binding_values(kind, mirror_action(kind, a)))(actions)
    m = NUM_MOTOR_BINDINGS
    np.testing.assert_array_equal(np.asarray(mirrored[:, :m]), -np.asarray(values[:, :m]))
    np.testing.assert_array_equal(np.asarray(mirrored[:, m:]), np.asarray(values[:, m:]))
    np.testing.assert_array_equal(np.asarray(mirror_action(kind, mirror_action(kind, actions))), np.asarray(actions))


def test_an_auto_motor_gets_the_negated_speed_and_a_bound_one_keeps_its_own():
    bound, auto = parse_level(CAR).build(), parse_level(AUTO_CAR).build()
    assert float(mirror_level(bound).physics.joints.motor_speed[0]) == 0.5
    assert float(mirror_level(auto).physics.joints.motor_speed[0]) == -0.5
    twice = mirror_level(mirror_level(auto))
    for a, b in zip(jax.tree.leaves(auto), jax.tree.leaves(twice), strict=True):
        np.testing.assert_allclose(np.asarray(b), np.asarray(a), rtol=0, atol=1e-6)  # [m]: 5 - x rounds each way


def test_the_pair_env_observes_the_state_and_its_mirror_image():
    level = parse_level(CAR).build()
    plain = KinetixEnv(SIZES["s"], observation="symbolic-entity")
    pair = MirrorPairEnv.of(plain)
    assert (pair.static, pair.observation, pair.action, pair.frame_skip) == (
        SIZES["s"],
        "symbolic-entity",
        "multi-discrete",
        2,
    )
    state = plain.initial_state(level)
    seen, mirror_image = pair.observe(state)
    for a, b in zip(jax.tree.leaves(seen), jax.tree.leaves(plain.observe(state)), strict=True):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    expected = plain.observe(mirror_env_state(state))
    for a, b in zip(jax.tree.leaves(mirror_image), jax.tree.leaves(expected), strict=True):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    # the mirror image is another state: the green chassis is seen on the other side
    assert not np.array_equal(np.asarray(jax.tree.leaves(seen)[0]), np.asarray(jax.tree.leaves(mirror_image)[0]))
