"""Kinetix for Gymnasium: a vector environment stepping the JAX environment in batches, and a single environment.

    import gymnasium, kinetix_cli.gym  # registers kinetix/Kinetix-v0
    envs = gymnasium.make_vec("kinetix/Kinetix-v0", num_envs=64, levels="s")
    env = gymnasium.make("kinetix/Kinetix-v0", levels="s")

Keyword arguments are `kinetix_cli.gym.make`'s (levels, size, observation, action, frame_skip, max_steps,
dense_reward_scale). Observations, rewards and flags are numpy arrays; actions are numpy arrays too. The vector
environment resets an ended episode in the same step (Gymnasium's `AutoresetMode.SAME_STEP`): the observation
returned is the new episode's, `infos["final_obs"]` holds the one the episode ended on (rows where
`infos["_final_obs"]`), and `infos["solved"]`, `infos["failed"]` say how it ended. Episodes are truncated by the
environment itself at `max_steps`.
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

from kinetix_cli.gym.environment import KinetixGymnax, MultiDiscrete, make

ENV_ID = "kinetix/Kinetix-v0"


class KinetixVectorEnv(VectorEnv):
    """`num_envs` Kinetix environments stepped as one batch by a jitted, vmapped `KinetixGymnax.step`."""

    metadata = {"autoreset_mode": AutoresetMode.SAME_STEP, "render_modes": []}

    def __init__(self, num_envs: int, **kwargs: Any) -> None:
        if not isinstance(num_envs, int) or num_envs < 1:
            raise gymnasium.error.Error(f"num_envs: expected a whole number >= 1, got {num_envs!r}")
        self.num_envs = num_envs
        self.env, self.params = make(**kwargs)
        self.single_observation_space = gymnasium_space(self.env.observation_space(self.params))
        self.single_action_space = gymnasium_space(self.env.action_space(self.params))
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._key = jax.random.key(0)
        self._state = None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)  # Gymnasium checks the seed (an int) and seeds np_random
        if seed is not None:
            self._key = jax.random.key(_seed(seed))
        self._key, key = jax.random.split(self._key)
        obs, self._state = _reset(self.env, jax.random.split(key, self.num_envs), self.params)
        return _host(obs), {}

    def step(self, actions):
        if self._state is None:
            raise gymnasium.error.ResetNeeded("call reset() before step()")
        self._key, key = jax.random.split(self._key)
        actions = jnp.asarray(np.asarray(actions, self.single_action_space.dtype))
        obs, self._state, reward, terminated, truncated, info = _step(
            self.env, jax.random.split(key, self.num_envs), self._state, actions, self.params
        )
        obs, reward, terminated, truncated, info = _host((obs, reward, terminated, truncated, info))
        done = terminated | truncated
        infos = {
            "final_obs": info["final_observation"],
            "_final_obs": done,
            "solved": info["solved"],
            "_solved": done,
            "failed": info["failed"],
            "_failed": done,
        }
        return obs, reward.astype(np.float32), terminated, truncated, infos


class KinetixGymnasiumEnv(gymnasium.Env):
    """One Kinetix environment for Gymnasium (a vector environment of one, unbatched)."""

    metadata = {"render_modes": []}

    def __init__(self, **kwargs: Any) -> None:
        self._vector = KinetixVectorEnv(1, **kwargs)
        self.observation_space = self._vector.single_observation_space
        self.action_space = self._vector.single_action_space

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        obs, info = self._vector.reset(seed=seed)
        return _first(obs), info

    def step(self, action):
        obs, reward, terminated, truncated, infos = self._vector.step(_batch_of_one(action))
        info = {"solved": bool(infos["solved"][0]), "failed": bool(infos["failed"][0])}
        if terminated[0] or truncated[0]:
            obs = infos["final_obs"]  # a single environment is not reset by itself: Gymnasium's caller resets it
        return _first(obs), float(reward[0]), bool(terminated[0]), bool(truncated[0]), info


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


@functools.partial(jax.jit, static_argnums=0)
def _reset(env: KinetixGymnax, keys, params):
    return jax.vmap(env.reset, in_axes=(0, None))(keys, params)


@functools.partial(jax.jit, static_argnums=0)
def _step(env: KinetixGymnax, keys, state, actions, params):
    return jax.vmap(env.step, in_axes=(0, 0, 0, None))(keys, state, actions, params)


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


def _first(obs):
    return {k: v[0] for k, v in obs.items()} if isinstance(obs, dict) else obs[0]


def _batch_of_one(action):
    return np.asarray(action)[None]


def _seed(seed: int) -> int:
    return int(seed) & 0x7FFFFFFF  # a non-negative int32: what jax.random.key takes on every platform
