"""Record one episode of a level and turn it into GIF frames (`kinetix rollout`).

`record_episode` plays the episode with the episode runner (`kinetix_cli.env.episode.run_episode`, `record=True`)
under any policy: an open-loop one (no-op, random, the level's solution) or a trained network sampling its
actions, in the environment the caller built (a run's own settings for a trained policy).
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import numpy as np

from kinetix_cli.env.actions import binding_values
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.episode import Policy, run_episode
from kinetix_cli.env.level import Level, share_engine_params, stack_levels, to_host
from kinetix_cli.viz.render import render_frame


@dataclasses.dataclass
class Episode:
    """A recorded episode (host numpy).

    Attributes:
        physics: engine `State` with a leading time axis: the start, then the state after each step
            (length + 1 entries).
        bindings: the level's bindings.
        action_type: the environment's action type (how `actions` read).
        actions: (length, ...) actions taken.
        rewards: (length,) rewards.
        solved, failed: how it ended (neither: it ran out of time).
        length: environment steps played.
        step_seconds: simulated time per environment step [s].
    """

    physics: object
    bindings: object
    action_type: str
    actions: np.ndarray
    rewards: np.ndarray
    solved: bool
    failed: bool
    length: int
    step_seconds: float

    @property
    def total_return(self) -> float:
        return float(self.rewards.sum())

    @property
    def ending(self) -> str:
        """How the episode ended: "solved", "failed" or "timed out"."""
        return "solved" if self.solved else "failed" if self.failed else "timed out"


def record_episode(
    env: KinetixEnv, params: EnvParams, level: Level, policy: Policy, key: jax.Array, horizon: int
) -> Episode:
    """Play one episode of `level` under `policy` and keep every state until it ends."""
    return record_episodes(env, params, [level], policy, key[None], horizon)[0]


def record_episodes(
    env: KinetixEnv, params: EnvParams, levels: list[Level], policy: Policy, keys: jax.Array, horizon: int
) -> list[Episode]:
    """Play one episode of each level (same size) under `policy`, level i with `keys[i]`, all in one batched
    rollout (one compile for the batch), and keep every state of each until it ends."""

    @functools.partial(jax.jit, static_argnums=2)
    def play(levels, keys, level_axes):
        episode = functools.partial(run_episode, env, params, policy=policy, horizon=horizon, record=True)
        return jax.vmap(lambda level, key: episode(level, key=key), in_axes=(level_axes, 0))(levels, keys)

    batch, level_axes = share_engine_params(stack_levels(levels))
    outcomes, traces = to_host(play(batch, keys, level_axes))
    episodes = []
    for i, level in enumerate(levels):
        length = int(outcomes.length[i])
        start = jax.tree.map(lambda x: np.asarray(x)[None], level.physics)
        frames = jax.tree.map(lambda a, b, i=i, n=length: np.concatenate([a, b[i, :n]]), start, traces.physics)
        episodes.append(
            Episode(
                physics=frames,
                bindings=to_host(level.bindings),
                action_type=env.action,
                actions=traces.action[i, :length],
                rewards=traces.reward[i, :length],
                solved=bool(outcomes.solved[i]),
                failed=bool(outcomes.failed[i]),
                length=length,
                step_seconds=env.frame_skip * float(level.engine_params.dt),
            )
        )
    return episodes


def episode_frames(title: str, episode: Episode, scale: float = 80, every: int = 1) -> list:
    """PIL frames of an episode (every `every`-th step, plus the last) with time and return captions."""
    returns = np.concatenate([[0.0], np.cumsum(episode.rewards)])
    picks = list(range(0, episode.length + 1, every))
    if picks[-1] != episode.length:
        picks.append(episode.length)
    frames = []
    for i in picks:
        physics = jax.tree.map(lambda x, i=i: x[i], episode.physics)
        action = None if i == 0 else np.asarray(binding_values(episode.action_type, episode.actions[i - 1]))
        status = ""
        if i == episode.length:
            status = "  solved" if episode.solved else "  failed" if episode.failed else ""
        caption = f"t = {i * episode.step_seconds:4.2f} s   step {i:3d}   return {returns[i]:+.2f}{status}"
        frames.append(
            render_frame(physics, episode.bindings, scale=scale, title=title, caption=caption, actions=action)
        )
    return frames
