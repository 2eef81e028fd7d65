"""Levels, environment states and actions mirrored left to right (`engine.mirror_state`: x -> 5 - x).

A level's mirror image is solved by the mirrored actions: every motor entry's direction reversed (forward and
backward swap), thrusters as they are (each thruster is mirrored with its body, so the same press pushes the mirror
way). Bindings stay: binding k drives the same motors and thrusters in both. An auto motor, which always runs
forward, gets the negated speed instead, so it turns the mirror way too.

`MirrorPairEnv` observes every state twice, as it is and mirrored: what a policy needs to average its action
distribution over a level and its reflection (`rl.networks.mirror_averaged_policy`).
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from engine import State, mirror_motor_actions, mirror_state
from kinetix_cli.constants import NUM_MOTOR_BINDINGS, NUM_THRUSTER_BINDINGS
from kinetix_cli.env.environment import EnvState, KinetixEnv
from kinetix_cli.env.level import Bindings, Level

DISCRETE_MIRROR = (
    0,
    *(c + 1 + (1 if c % 2 == 0 else -1) for c in range(2 * NUM_MOTOR_BINDINGS)),
    *range(2 * NUM_MOTOR_BINDINGS + 1, 2 * NUM_MOTOR_BINDINGS + 1 + NUM_THRUSTER_BINDINGS),
)
"""The ``discrete`` choice that mirrors each choice: no-op and thrusters stay, each motor's forward and backward
swap (1 <-> 2, 3 <-> 4, ...)."""
MULTI_DISCRETE_MIRROR = (0, 2, 1)
"""The mirror of each choice of a ``multi-discrete`` motor entry: off stays, forward <-> backward."""


def _mirror_physics(physics: State, bindings: Bindings) -> State:
    mirrored = mirror_state(physics)
    joints = mirrored.joints
    return mirrored.replace(
        joints=joints.replace(motor_speed=jnp.where(bindings.motor_auto, -1, 1) * joints.motor_speed)
    )


def mirror_level(level: Level) -> Level:
    """The mirror image of one level (no batch axis; vmap it for a batch); mirroring twice gives the level back."""
    return level.replace(physics=_mirror_physics(level.physics, level.bindings))


def mirror_env_state(state: EnvState) -> EnvState:
    """The mirror image of an environment state (what the agent would see in the mirrored level)."""
    return state.replace(physics=_mirror_physics(state.physics, state.bindings))


def mirror_action(kind: str, action: jax.Array) -> jax.Array:
    """The action of type `kind` that does in the mirror image what `action` does in the level."""
    m = NUM_MOTOR_BINDINGS
    if kind == "multi-discrete":
        action = jnp.asarray(action, jnp.int32)
        return action.at[..., :m].set(jnp.asarray(MULTI_DISCRETE_MIRROR, jnp.int32)[action[..., :m]])
    if kind == "discrete":
        return jnp.asarray(DISCRETE_MIRROR, jnp.int32)[jnp.asarray(action, jnp.int32)]
    if kind == "continuous":
        action = jnp.asarray(action, jnp.float32)
        return action.at[..., :m].set(mirror_motor_actions(action[..., :m]))
    raise ValueError(f"unknown action type {kind!r}")


@dataclasses.dataclass(frozen=True)
class MirrorPairEnv(KinetixEnv):
    """A `KinetixEnv` whose observation is the pair (observation, observation of the mirrored state)."""

    @classmethod
    def of(cls, env: KinetixEnv) -> MirrorPairEnv:
        """The same environment (size, observation, action type, frame skip), observing pairs."""
        return cls(**{field.name: getattr(env, field.name) for field in dataclasses.fields(env)})

    def observe(self, state: EnvState):
        return super().observe(state), super().observe(mirror_env_state(state))
