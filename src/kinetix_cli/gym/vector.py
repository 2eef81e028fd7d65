"""Kinetix for Gymnasium: a vector environment stepping the JAX environment in batches, and a single environment.

Keyword arguments are `kinetix_cli.gym.make`'s (levels, size, observation, action, frame_skip, max_steps,
dense_reward_scale, fresh_levels) and `render_mode` (None or "rgb_array"). Observations, rewards and flags are numpy
arrays; actions are numpy arrays too. The vector environment resets an ended episode in the same step (Gymnasium's
`AutoresetMode.SAME_STEP`): the observation returned is the new episode's, `infos["final_obs"]` holds the one the
episode ended on (rows where `infos["_final_obs"]`), and `infos["solved"]`, `infos["failed"]` say how it ended.
The single environment does not reset by itself: its caller resets it, as Gymnasium's API has it. Episodes are
truncated by the environment itself at `max_steps`.

With `levels="fresh"` both draw a new batch of fresh levels (`KinetixGymnax.refresh_levels`) each time as many
episodes have started since the last batch as a batch holds (`fresh_levels`), and at each reset with a seed, so that
a seed gives the same levels.

Examples:
    >>> import gymnasium
    >>> import kinetix_cli.gym  # registers kinetix/Kinetix-v0
    >>> envs = gymnasium.make_vec("kinetix/Kinetix-v0", num_envs=64, levels="s")
    >>> envs.observation_space.shape, envs.single_action_space
    ((64, 140), MultiDiscrete([3 3 3 3 2 2]))
    >>> env = gymnasium.make("kinetix/Kinetix-v0", levels="s", render_mode="rgb_array")
    >>> env.action_space
    MultiDiscrete([3 3 3 3 2 2])
"""

from __future__ import annotations

import functools
from typing import Any

import gymnasium
import jax
import jax.numpy as jnp
import numpy as np
from gymnasium import spaces as gym_spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space
from gymnax.environments import spaces as gymnax_spaces

from kinetix_cli.env.actions import binding_values
from kinetix_cli.env.environment import EnvParams, EnvState, KinetixEnv
from kinetix_cli.env.level import level_count
from kinetix_cli.gym.environment import KinetixGymnax, MultiDiscrete, make
from kinetix_cli.viz.render import render_frame

ENV_ID = "kinetix/Kinetix-v0"

RENDER_MODES = ["rgb_array"]
"""Gymnasium render modes: "rgb_array", an (H, W, 3) uint8 picture of the scene from `render_frame`."""

RENDER_SCALE = 50
"""Pixels per metre of a rendered frame: 260 x 282 pixels (width x height; both even, as video encoders need)."""


class _LevelDraws:
    """The gymnax environment and params behind a Gymnasium environment, its random key, and when fresh levels are
    drawn: with `levels="fresh"`, a new batch each time as many episodes have started since the last one as a batch
    holds, and one at each seeded reset.

    Attributes:
        env: the gymnax environment (`make(**kwargs)`).
        params: its params; with fresh levels, the pool is the current batch.
        key: the random key the next resets, steps and batches split from.
        started: episodes started since the last batch of fresh levels.
    """

    def __init__(self, kwargs: dict) -> None:
        self.env, self.params = make(**kwargs)
        self.key = jax.random.key(0)
        self.started = 0

    def next_key(self) -> jax.Array:
        self.key, key = jax.random.split(self.key)
        return key

    def seed(self, seed: int | None) -> None:
        """Start the key stream of `seed` (and with fresh levels, a batch drawn from it); None: carry on."""
        if seed is None:
            return
        self.key = jax.random.key(_seed(seed))
        if self.env.fresh is not None:
            self.params = self.env.refresh_levels(self.next_key(), self.params)
            self.started = 0

    def episodes_started(self, count: int) -> None:
        """Count `count` new episodes; draw the next batch of fresh levels once a batch's worth have started."""
        if self.env.fresh is None:
            return
        self.started += count
        if self.started >= level_count(self.params.pool):
            self.params = self.env.refresh_levels(self.next_key(), self.params)
            self.started = 0

    def render_fps(self) -> float:
        """Environment steps per simulated second: 1 / (frame_skip x dt of the pool's first level)."""
        dt = float(self.params.pool.engine_params.dt[0])
        return 1.0 / (self.env.env.frame_skip * dt)


class KinetixVectorEnv(VectorEnv):
    """`num_envs` Kinetix environments stepped as one batch by a jitted, vmapped `KinetixGymnax.step`.

    `render()` (with `render_mode="rgb_array"`) returns one picture, of the first environment's current state:
    after a step in which its episode ended, the new episode's start. Gymnasium's own vector environments return
    a tuple of one picture per environment; drawing all of them costs ~40 ms each on the host.
    """

    metadata = {"autoreset_mode": AutoresetMode.SAME_STEP, "render_modes": RENDER_MODES}

    def __init__(self, num_envs: int, render_mode: str | None = None, **kwargs: Any) -> None:
        if not isinstance(num_envs, int) or num_envs < 1:
            raise gymnasium.error.Error(f"num_envs: expected a whole number >= 1, got {num_envs!r}")
        self.num_envs = num_envs
        self.render_mode = _render_mode(render_mode)
        self._draws = _LevelDraws(kwargs)
        self.env = self._draws.env
        self.metadata = {**type(self).metadata, "render_fps": self._draws.render_fps()}
        self.single_observation_space = gymnasium_space(self.env.observation_space(self._draws.params))
        self.single_action_space = gymnasium_space(self.env.action_space(self._draws.params))
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._state = None
        self._first_action = None

    @property
    def params(self):
        """The gymnax params the next step runs with (with fresh levels, the current batch in `params.pool`)."""
        return self._draws.params

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)  # Gymnasium checks the seed (an int) and seeds np_random
        self._draws.seed(seed)
        keys = jax.random.split(self._draws.next_key(), self.num_envs)
        obs, self._state = _reset(self.env, keys, self.params)
        self._first_action = None
        self._draws.episodes_started(self.num_envs)
        return _host(obs), {}

    def step(self, actions):
        if self._state is None:
            raise gymnasium.error.ResetNeeded("call reset() before step()")
        keys = jax.random.split(self._draws.next_key(), self.num_envs)
        actions = np.asarray(actions, self.single_action_space.dtype)
        obs, self._state, reward, terminated, truncated, info = _step(
            self.env, keys, self._state, jnp.asarray(actions), self.params
        )
        kept = {name: info[name] for name in ("final_observation", "solved", "failed")}
        obs, reward, terminated, truncated, info = _host((obs, reward, terminated, truncated, kept))
        done = terminated | truncated
        self._first_action = None if done[0] else actions[0]
        self._draws.episodes_started(int(done.sum()))
        infos = {
            "final_obs": info["final_observation"],
            "_final_obs": done,
            "solved": info["solved"],
            "_solved": done,
            "failed": info["failed"],
            "_failed": done,
        }
        return obs, reward.astype(np.float32), terminated, truncated, infos

    def render(self) -> np.ndarray | None:
        """(H, W, 3) uint8: the first environment's current state, or None without a render mode."""
        if self._state is None:
            raise gymnasium.error.ResetNeeded("call reset() before render()")
        return _render(self, jax.tree.map(lambda x: x[0], self._state), self._first_action)


class KinetixGymnasiumEnv(gymnasium.Env):
    """One Kinetix environment for Gymnasium, unbatched. A step that ends an episode leaves the environment on the
    episode's last state (what `render()` draws) until the caller resets it."""

    metadata = {"render_modes": RENDER_MODES}

    def __init__(self, render_mode: str | None = None, **kwargs: Any) -> None:
        self.render_mode = _render_mode(render_mode)
        self._draws = _LevelDraws(kwargs)
        self.env = self._draws.env
        self.metadata = {**type(self).metadata, "render_fps": self._draws.render_fps()}
        self.observation_space = gymnasium_space(self.env.observation_space(self._draws.params))
        self.action_space = gymnasium_space(self.env.action_space(self._draws.params))
        self._state = None
        self._action = None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self._draws.seed(seed)
        obs, self._state = self.env.reset(self._draws.next_key(), self._draws.params)
        self._action = None
        self._draws.episodes_started(1)
        return _host(obs), {}

    def step(self, action):
        if self._state is None:
            raise gymnasium.error.ResetNeeded("call reset() before step()")
        self._action = np.asarray(action, self.action_space.dtype)
        obs, self._state, reward, terminated, truncated, info = _step_one(
            self.env.env, self._state, jnp.asarray(self._action), self._draws.params.env_params
        )
        obs, reward, terminated, truncated, solved, failed = _host(
            (obs, reward, terminated, truncated, info["solved"], info["failed"])
        )
        info = {"solved": bool(solved), "failed": bool(failed)}
        return obs, float(reward), bool(terminated), bool(truncated), info

    def render(self) -> np.ndarray | None:
        """(H, W, 3) uint8: the environment's current state, or None without a render mode."""
        if self._state is None:
            raise gymnasium.error.ResetNeeded("call reset() before render()")
        return _render(self, self._state, self._action)


def gymnasium_space(space: gymnax_spaces.Space) -> gym_spaces.Space:
    """The Gymnasium space of a `KinetixGymnax` space."""
    if isinstance(space, MultiDiscrete):
        return gym_spaces.MultiDiscrete(np.asarray(space.nvec), dtype=np.int32)
    if isinstance(space, gymnax_spaces.Discrete):
        return gym_spaces.Discrete(space.n)
    if isinstance(space, gymnax_spaces.Box):
        dtype = np.dtype(space.dtype)
        low, high = (np.broadcast_to(np.asarray(x, dtype), space.shape) for x in (space.low, space.high))
        if dtype == np.bool_:
            return gym_spaces.MultiBinary(space.shape)
        return gym_spaces.Box(low, high, space.shape, dtype)
    if isinstance(space, gymnax_spaces.Dict):
        return gym_spaces.Dict({name: gymnasium_space(sub) for name, sub in space.spaces.items()})
    raise TypeError(f"no Gymnasium space for {space!r}")


def render_state(env: KinetixGymnax, state: EnvState, action=None) -> np.ndarray:
    """(H, W, 3) uint8 picture of one environment's state (`render_frame` at `RENDER_SCALE`), captioned with the
    episode's time and step; with the `action` that led to it, firing thrusters and running motors show."""
    state = jax.device_get(state)
    steps = int(state.steps)
    seconds = steps * env.env.frame_skip * float(state.engine_params.dt)
    values = None if action is None else np.asarray(binding_values(env.env.action, action))
    image = render_frame(
        state.physics,
        state.bindings,
        scale=RENDER_SCALE,
        title=env.name,
        caption=f"t = {seconds:4.2f} s   step {steps:3d}",
        actions=values,
    )
    return np.asarray(image, np.uint8)


def _render(owner, state: EnvState, action) -> np.ndarray | None:
    if owner.render_mode is None:
        gymnasium.logger.warn('render() without a render_mode: make the environment with render_mode="rgb_array"')
        return None
    return render_state(owner.env, state, action)


def _render_mode(mode: str | None) -> str | None:
    if mode is not None and mode not in RENDER_MODES:
        raise gymnasium.error.Error(f"render_mode: {mode!r} is not one of {', '.join(RENDER_MODES)} (or None)")
    return mode


@functools.partial(jax.jit, static_argnums=0)
def _reset(env: KinetixGymnax, keys, params):
    return jax.vmap(env.reset, in_axes=(0, None))(keys, params)


@functools.partial(jax.jit, static_argnums=0)
def _step(env: KinetixGymnax, keys, state, actions, params):
    return jax.vmap(env.step, in_axes=(0, 0, 0, None))(keys, state, actions, params)


@functools.partial(jax.jit, static_argnums=0)
def _step_one(env: KinetixEnv, state: EnvState, action, params: EnvParams):
    return env.step_env(state, action, params)


def _host(tree):
    """Device arrays (an entity observation's fields as a dict) -> numpy."""
    tree = jax.device_get(tree)
    if hasattr(tree, "__dataclass_fields__"):
        return {name: np.asarray(getattr(tree, name)) for name in tree.__dataclass_fields__}
    if isinstance(tree, tuple):
        return tuple(_host(x) for x in tree)
    if isinstance(tree, dict):
        return {k: _host(v) for k, v in tree.items()}
    return np.asarray(tree)


def _seed(seed: int) -> int:
    return int(seed) & 0x7FFFFFFF  # a non-negative int32: what jax.random.key takes on every platform
