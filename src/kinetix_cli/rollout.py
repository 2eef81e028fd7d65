"""Record one episode of a level under a simple policy, for `kinetix rollout` (GIF) and inspection.

Policies: ``noop`` (press nothing), ``random`` (uniform multi-discrete action every step, seeded) and
``solution`` (the level file's stored action sequence). Checkpoint policies arrive with PPO.
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np

from kinetix_cli.actions import action_space
from kinetix_cli.env import EnvConfig, EnvParams, KinetixEnv, reset_to
from kinetix_cli.errors import UserError
from kinetix_cli.level import Level
from kinetix_cli.level_file import LevelSpec
from kinetix_cli.solve import ACTION_WIDTH, decode_solution, make_env

POLICIES = ("noop", "random", "solution")


@dataclasses.dataclass
class Episode:
    """A recorded episode (host numpy).

    Attributes:
        physics: engine `State` with a leading time axis: the start, then the state after each step
            (length + 1 entries).
        bindings: the level's bindings.
        actions: (length, 6) multi-discrete actions taken.
        rewards: (length,) rewards.
        solved, failed: how it ended (neither: it ran out of time).
        length: environment steps played.
        step_seconds: simulated time per environment step [s].
    """

    physics: object
    bindings: object
    actions: np.ndarray
    rewards: np.ndarray
    solved: bool
    failed: bool
    length: int
    step_seconds: float

    @property
    def total_return(self) -> float:
        return float(self.rewards.sum())


def policy_actions(spec: LevelSpec, policy: str, horizon: int, seed: int = 0) -> np.ndarray:
    """(horizon, 6) int32 multi-discrete actions of an open-loop policy."""
    if policy == "noop":
        return np.zeros((horizon, ACTION_WIDTH), np.int32)
    if policy == "random":
        nvec = np.asarray(action_space("multi-discrete").nvec)
        return (np.random.default_rng(seed).random((horizon, ACTION_WIDTH)) * nvec).astype(np.int32)
    if policy == "solution":
        if spec.solution is None:
            raise UserError(f"{spec.path or spec.name}: solution: the level ships no solution (try --policy random)")
        return decode_solution(spec.solution, spec.path or spec.name, horizon)
    raise UserError(f"--policy: unknown policy {policy!r}; choose one of {', '.join(POLICIES)}")


@functools.partial(jax.jit, static_argnums=(0,))
def _trace(config: EnvConfig, params: EnvParams, level: Level, actions: jax.Array):
    env = KinetixEnv(config, reset_to(level))

    def body(state, action):
        state, reward, done, info = env.step_env(state, action, params)
        return state, (state.physics, reward, done, info["solved"], info["failed"])

    return jax.lax.scan(body, env.state_from_level(level), actions)[1]


def record_episode(spec: LevelSpec, policy: str, seed: int = 0, static=None, actions=None) -> Episode:
    """Play one episode of `spec` under `policy` (or the given (H, 6) `actions`) and keep every state until it
    ends."""
    config, params, level = make_env(spec, static)
    if actions is None:
        actions = policy_actions(spec, policy, int(params.max_steps), seed)
    physics, rewards, done, solved, failed = jax.device_get(_trace(config, params, level, jnp.asarray(actions)))
    length = int(np.argmax(done)) + 1 if done.any() else len(done)
    start = jax.tree.map(lambda x: np.asarray(x)[None], level.physics)
    frames = jax.tree.map(lambda a, b: np.concatenate([a, b[:length]]), start, physics)
    return Episode(
        physics=frames,
        bindings=jax.device_get(level.bindings),
        actions=actions[:length],
        rewards=rewards[:length],
        solved=bool(solved[length - 1]),
        failed=bool(failed[length - 1]),
        length=length,
        step_seconds=config.frame_skip * float(params.engine.dt),
    )


def episode_frames(spec: LevelSpec, episode: Episode, scale: float = 80, every: int = 1) -> list:
    """PIL frames of an episode (every `every`-th step, plus the last) with time and return captions."""
    from kinetix_cli.actions import binding_values
    from kinetix_cli.render import render_frame

    returns = np.concatenate([[0.0], np.cumsum(episode.rewards)])
    picks = list(range(0, episode.length + 1, every))
    if picks[-1] != episode.length:
        picks.append(episode.length)
    frames = []
    for i in picks:
        physics = jax.tree.map(lambda x, i=i: x[i], episode.physics)
        action = None if i == 0 else np.asarray(binding_values("multi-discrete", episode.actions[i - 1]))
        status = ""
        if i == episode.length:
            status = "  solved" if episode.solved else "  failed" if episode.failed else ""
        caption = f"t = {i * episode.step_seconds:4.2f} s   step {i:3d}   return {returns[i]:+.2f}{status}"
        frames.append(
            render_frame(physics, episode.bindings, scale=scale, title=spec.name, caption=caption, actions=action)
        )
    return frames
