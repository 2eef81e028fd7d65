"""The Kinetix environment: make green touch blue, never green touch red.

The interface, in the style of gymnax 1.0 and JaxUED (every function pure, jittable and vmappable):

- `env = KinetixEnv(static, observation, action, frame_skip)`: frozen and hashable, so it is a static argument of
  `jax.jit`; equal settings share one compile. `params = env.default_params` (`EnvParams`) is traced. Its
  `reset_to_level`, `step_env`, `step` and `observe` are jitted with the environment static: inside a rollout, an
  evaluation or curriculum scoring each is one nested call, traced once per environment and shared by every
  program that steps it (XLA inlines it; what is computed is unchanged).
- `obs, state = env.reset_to_level(level)`: start an episode from an explicit `Level`.
- `obs, state, reward, terminated, truncated, info = env.step_env(state, action, params)`: one step, no reset.
- `obs, state, reward, terminated, truncated, info = env.step(state, action, params, reset_level)`: one step;
  an episode that ended restarts from `reset_level` (drawn by the caller's level source), and
  `info["final_observation"]` is the observation after the step, before the reset.

The environment is deterministic: no step takes a random key. Per environment step the action is held for
`frame_skip` engine steps. Each engine step scores the task: any green-red contact -> -1 (takes priority), else
any green-blue contact -> +1; the first non-zero score terminates the episode. Optional dense shaping adds
-(d_t - d_{t-1}) * dense_reward_scale, with d the summed green-blue centre distance (potential-based: also on the
first step, from the distance at reset). A state that stops being finite terminates the episode with reward 0;
`max_steps` steps truncate it.
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import jax.numpy as jnp
from flax import struct

import engine
from engine import Params, State, Static, pair_table
from kinetix_cli.config import EnvSettings
from kinetix_cli.constants import BLUE, GREEN, OBSERVATION_TYPES, RED
from kinetix_cli.env.actions import ACTION_TYPES, ActionSpace, action_space, binding_values, engine_actions
from kinetix_cli.env.level import Bindings, Level
from kinetix_cli.env.observations import symbolic_entity, symbolic_flat
from kinetix_cli.env.pixels import pixel_observation


@struct.dataclass
class EnvParams:
    """Traced environment settings, shared by every level (defaults: the experiment config's, `EnvSettings`).

    Attributes:
        max_steps: episode cap in environment steps (256 = ~8.5 s at frame skip 2).
        dense_reward_scale: weight of the green-blue distance shaping; 0 turns it off.
    """

    max_steps: int = EnvSettings.max_steps
    dense_reward_scale: float = EnvSettings.dense_reward_scale


@struct.dataclass
class EnvState:
    """One environment.

    Attributes:
        physics: engine state.
        bindings: action bindings of the current level.
        engine_params: engine constants of the current level.
        steps: () int32 environment steps taken in this episode.
        distance: () float32 summed green-blue centre distance at the last step [m].
    """

    physics: State
    bindings: Bindings
    engine_params: Params
    steps: jax.Array
    distance: jax.Array


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


def select_episodes(done: jax.Array, reset: EnvState, stepped: EnvState) -> EnvState:
    """`reset` where `done`, else `stepped`: one tree-wide select (`done` () for one env, (B,) for a batch)."""

    def pick(a, b):
        return jnp.where(done.reshape(done.shape + (1,) * (a.ndim - done.ndim)), a, b)

    return jax.tree.map(pick, reset, stepped)


@dataclasses.dataclass(frozen=True)
class KinetixEnv:
    """The environment for one size, observation type, action type and frame skip.

    Attributes:
        static: engine capacities (the level size); levels of this size share one compile.
        observation: one of `constants.OBSERVATION_TYPES`; only this one is computed.
        action: one of `constants.ACTION_TYPES` (see `kinetix_cli.env.actions`).
        frame_skip: engine steps per environment step.
        attention: whether a ``symbolic-entity`` observation computes its ``attention_mask`` (which only the
            transformer reads; it tests every pair of shapes for contact). False: the mask is all False and costs
            nothing (`ModelSettings.reads_attention` says which models need it).
    """

    static: Static
    observation: str = "symbolic-flat"
    action: str = "multi-discrete"
    frame_skip: int = 2
    attention: bool = True

    def __post_init__(self) -> None:
        if self.observation not in OBSERVATION_TYPES:
            raise ValueError(f"unknown observation {self.observation!r}; choose one of {', '.join(OBSERVATION_TYPES)}")
        if self.action not in ACTION_TYPES:
            raise ValueError(f"unknown action type {self.action!r}; choose one of {', '.join(ACTION_TYPES)}")
        if self.frame_skip < 1:
            raise ValueError(f"frame_skip must be >= 1, got {self.frame_skip}")

    @property
    def action_space(self) -> ActionSpace:
        return action_space(self.action)

    @property
    def default_params(self) -> EnvParams:
        """`EnvParams()` (a property, as in gymnax)."""
        return EnvParams()

    @functools.partial(jax.jit, static_argnums=0)  # self: frozen and hashable
    def reset_to_level(self, level: Level):
        """Start an episode from `level`. Returns (observation, EnvState)."""
        state = self.initial_state(level)
        return self.observe(state), state

    def initial_state(self, level: Level) -> EnvState:
        """The `EnvState` at the start of an episode of `level` (no observation)."""
        physics = jax.tree.map(jnp.asarray, level.physics)
        return EnvState(
            physics=physics,
            bindings=jax.tree.map(jnp.asarray, level.bindings),
            engine_params=jax.tree.map(jnp.asarray, level.engine_params),
            steps=jnp.zeros((), jnp.int32),
            distance=green_blue_distance(physics),
        )

    @functools.partial(jax.jit, static_argnums=0)  # self: frozen and hashable
    def step_env(self, state: EnvState, action: jax.Array, params: EnvParams):
        """One environment step without reset.

        Returns (observation, state, reward, terminated, truncated, info): `terminated` when the task scored
        (green touched blue or red) or the state stopped being finite, `truncated` when the episode reached
        `params.max_steps` without terminating. info: `solved` (+1 end), `failed` (-1 end), `distance`
        (green-blue, after this step), `dropped_contacts`.
        """
        static = self.static
        actions = engine_actions(state.bindings, binding_values(self.action, action))

        def substep(carry, _):
            physics, score = carry
            physics, step_info = engine.step(static, state.engine_params, physics, actions)
            score = jnp.where(score != 0, score, task_score(static, physics, step_info.touching))
            return (physics, score), step_info.dropped_contacts

        (physics, score), dropped = jax.lax.scan(
            substep, (state.physics, jnp.zeros((), jnp.float32)), None, length=self.frame_skip
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
            "distance": distance,
            "dropped_contacts": dropped.sum(),
        }
        state = state.replace(physics=physics, steps=steps, distance=distance)
        return self.observe(state), state, reward, terminated, truncated, info

    @functools.partial(jax.jit, static_argnums=0)  # self: frozen and hashable
    def step(self, state: EnvState, action: jax.Array, params: EnvParams, reset_level: Level):
        """One environment step; an episode that ends restarts from `reset_level`.

        Returns (observation, state, reward, terminated, truncated, info) as `step_env`, where the observation
        and state of an ended episode are those of the new one and `info["final_observation"]` is the
        observation after the step, before any reset (a truncated episode bootstraps from it). A caller that
        does not use it does not pay for it: the observation is computed once, after the reset, and the final
        one only where it is read.
        """
        final_obs, stepped, reward, terminated, truncated, info = self.step_env(state, action, params)
        state = select_episodes(terminated | truncated, self.initial_state(reset_level), stepped)
        return self.observe(state), state, reward, terminated, truncated, info | {"final_observation": final_obs}

    @functools.partial(jax.jit, static_argnums=0)  # self: frozen and hashable
    def observe(self, state: EnvState):
        """The configured observation of a state."""
        if self.observation == "symbolic-flat":
            return symbolic_flat(self.static, state.physics, state.bindings)
        if self.observation == "symbolic-entity":
            return symbolic_entity(self.static, state.physics, state.bindings, self.attention)
        return pixel_observation(self.static, state.physics, state.bindings)
