"""The Kinetix environment: make green touch blue, never green touch red.

gymnax-style and pure: `env.reset(key, params)` and `env.step(key, state, action, params)` are jittable and
vmappable; `EnvConfig` is static (a change recompiles), `EnvParams` is traced. Episodes auto-reset to a level
drawn by the environment's reset function (one level, a device pool of levels, or a generator), or to a level
passed explicitly.

Per environment step the action is held for `frame_skip` engine steps. Each engine step scores the task:
any green-red contact -> -1 (takes priority), else any green-blue contact -> +1; the first non-zero score
ends the episode. Optional dense shaping adds -(d_t - d_{t-1}) * dense_reward_scale, with d the summed
green-blue centre distance (potential-based: also on the first step, from the distance at reset). An
episode also ends after `max_steps` steps (truncated) or when the state stops being finite (reward 0).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import jax
import jax.numpy as jnp
import numpy as np
from flax import struct

import engine
from engine import Params, State, Static
from engine.pairs import pair_table
from kinetix_cli.actions import ACTION_TYPES, action_space, binding_values, engine_actions
from kinetix_cli.level import Bindings, Level
from kinetix_cli.observations import symbolic_entity, symbolic_flat
from kinetix_cli.pixels import pixel_observation

OBSERVATION_TYPES = ("symbolic-flat", "symbolic-entity", "pixels")
GREEN, BLUE, RED = 1, 2, 3


@dataclasses.dataclass(frozen=True)
class EnvConfig:
    """Static environment settings.

    Attributes:
        static: engine capacities (the level size).
        observation: 'symbolic-flat', 'symbolic-entity' or 'pixels'; only this one is computed.
        action: 'multi-discrete', 'discrete' or 'continuous' (see `kinetix_cli.actions`).
        frame_skip: engine steps per environment step.
    """

    static: Static
    observation: str = "symbolic-flat"
    action: str = "multi-discrete"
    frame_skip: int = 2

    def __post_init__(self) -> None:
        if self.observation not in OBSERVATION_TYPES:
            raise ValueError(f"unknown observation {self.observation!r}; choose one of {', '.join(OBSERVATION_TYPES)}")
        if self.action not in ACTION_TYPES:
            raise ValueError(f"unknown action type {self.action!r}; choose one of {', '.join(ACTION_TYPES)}")
        if self.frame_skip < 1:
            raise ValueError(f"frame_skip must be >= 1, got {self.frame_skip}")


@struct.dataclass
class EnvParams:
    """Traced environment settings.

    Attributes:
        engine: physical constants.
        max_steps: episode cap in environment steps (256 = ~8.5 s at frame skip 2).
        dense_reward_scale: weight of the green-blue distance shaping; 0 turns it off.
    """

    engine: Params = Params()
    max_steps: int = 256
    dense_reward_scale: float = 0.1


@struct.dataclass
class EnvState:
    """One environment.

    Attributes:
        physics: engine state.
        bindings: action bindings of the current level.
        steps: () int32 environment steps taken in this episode.
        distance: () float32 summed green-blue centre distance at the last step [m].
    """

    physics: State
    bindings: Bindings
    steps: jax.Array
    distance: jax.Array


ResetFn = Callable[[jax.Array], Level]
"""key -> Level: the level a finished episode restarts from."""


def reset_to(level: Level) -> ResetFn:
    """Always restart from `level` (a single level, device or numpy leaves)."""
    level = jax.tree.map(jnp.asarray, level)
    return lambda key: level


def reset_from_pool(levels: Level) -> ResetFn:
    """Restart from a uniformly drawn level of a batch `levels` (leading axis) kept on the device."""
    levels = jax.tree.map(jnp.asarray, levels)
    count = jax.tree.leaves(levels)[0].shape[0]
    return lambda key: jax.tree.map(lambda x: x[jax.random.randint(key, (), 0, count)], levels)


def green_blue_distance(physics: State) -> jax.Array:
    """() summed centre distance over every active (green, blue) body pair [m]."""
    b = physics.bodies
    green = b.active & (b.role == GREEN)
    blue = b.active & (b.role == BLUE)
    gap = jnp.linalg.norm(b.position[:, None, :] - b.position[None, :, :] + 1e-12, axis=-1)
    return jnp.sum(jnp.where(green[:, None] & blue[None, :], gap, 0.0))


def task_score(static: Static, physics: State, touching: jax.Array) -> jax.Array:
    """() float32: -1 if any green-red pair touches, else +1 if any green-blue pair does, else 0.

    touching: (num_pairs,) from `engine.StepInfo`.
    """
    table = pair_table(static)
    role = physics.bodies.role
    ra, rb = role[jnp.asarray(table.a)], role[jnp.asarray(table.b)]

    def any_pair(x, y):
        return jnp.any(touching & (((ra == x) & (rb == y)) | ((ra == y) & (rb == x))))

    return jnp.where(any_pair(GREEN, RED), -1.0, jnp.where(any_pair(GREEN, BLUE), 1.0, 0.0))


def is_finite(physics: State) -> jax.Array:
    """() bool: every body position, angle and velocity is finite."""
    b = physics.bodies
    leaves = (b.position, b.angle, b.velocity, b.angular_velocity)
    return jnp.all(jnp.stack([jnp.all(jnp.isfinite(x)) for x in leaves]))


class KinetixEnv:
    """The environment for one size, observation type and action type.

    Args:
        config: static settings.
        reset_fn: where finished episodes restart (`reset_to`, `reset_from_pool`, or a generator).
    """

    def __init__(self, config: EnvConfig, reset_fn: ResetFn) -> None:
        self.config = config
        self.reset_fn = reset_fn
        self.action_space = action_space(config.action)

    @property
    def static(self) -> Static:
        return self.config.static

    @property
    def default_params(self) -> EnvParams:
        """`EnvParams()` (a property, as in gymnax)."""
        return EnvParams()

    # --- API ------------------------------------------------------------------------------------
    def reset(self, key: jax.Array, params: EnvParams, level: Level | None = None):
        """Start an episode from `level`, or from `reset_fn(key)`. Returns (observation, EnvState)."""
        state = self.state_from_level(self.reset_fn(key) if level is None else level)
        return self.observe(state), state

    def step(self, key: jax.Array, state: EnvState, action: jax.Array, params: EnvParams, reset_level=None):
        """Act for one environment step; a finished episode restarts (from `reset_level` if given).

        Returns (observation, state, reward, done, info); the observation and state of a finished
        episode are those of the new one. info: `solved` (+1 end), `failed` (-1 end), `truncated` (cap),
        `distance` (green-blue, at the end of this step), `dropped_contacts`.
        """
        next_state, reward, done, info = self.step_env(state, action, params)
        fresh = self.state_from_level(self.reset_fn(key) if reset_level is None else reset_level)
        state = jax.tree.map(lambda a, b: jnp.where(done, a, b), fresh, next_state)
        return self.observe(state), state, reward, done, info

    # --- pieces ---------------------------------------------------------------------------------
    def state_from_level(self, level: Level) -> EnvState:
        physics = jax.tree.map(jnp.asarray, level.physics)
        return EnvState(
            physics=physics,
            bindings=jax.tree.map(jnp.asarray, level.bindings),
            steps=jnp.zeros((), jnp.int32),
            distance=green_blue_distance(physics),
        )

    def step_env(self, state: EnvState, action: jax.Array, params: EnvParams):
        """The step without reset: (EnvState, reward, done, info)."""
        static = self.static
        actions = engine_actions(state.bindings, binding_values(self.config.action, action))

        def substep(carry, _):
            physics, score = carry
            physics, step_info = engine.step(static, params.engine, physics, actions)
            score = jnp.where(score != 0, score, task_score(static, physics, step_info.touching))
            return (physics, score), step_info.dropped_contacts

        (physics, score), dropped = jax.lax.scan(
            substep, (state.physics, jnp.zeros((), jnp.float32)), None, length=self.config.frame_skip
        )
        finite = is_finite(physics)
        distance = green_blue_distance(physics)
        shaping = -(distance - state.distance) * params.dense_reward_scale
        reward = jnp.where(finite, score + shaping, 0.0)
        steps = state.steps + 1
        terminated = (score != 0) | ~finite
        truncated = ~terminated & (steps >= params.max_steps)
        info = {
            "solved": finite & (score > 0),
            "failed": finite & (score < 0),
            "truncated": truncated,
            "distance": distance,
            "dropped_contacts": dropped.sum(),
        }
        next_state = state.replace(physics=physics, steps=steps, distance=distance)
        return next_state, reward, terminated | truncated, info

    def observe(self, state: EnvState):
        """The configured observation of a state."""
        kind = self.config.observation
        if kind == "symbolic-flat":
            return symbolic_flat(self.static, state.physics, state.bindings)
        if kind == "symbolic-entity":
            return symbolic_entity(self.static, state.physics, state.bindings)
        return pixel_observation(self.static, state.physics, state.bindings)


def as_numpy(tree):
    """Device tree -> numpy tree (for host-side rendering and files)."""
    return jax.tree.map(np.asarray, tree)
