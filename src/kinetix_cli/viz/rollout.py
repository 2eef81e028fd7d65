"""Record one episode of a level and turn it into GIF frames (`kinetix rollout`).

`record_episode` plays the episode with the episode runner (`kinetix_cli.env.episode.run_episode`, `record=True`)
under any policy: an open-loop one (no-op, random, the level's solution) or a trained network sampling its
actions, in the environment the caller built (a run's own settings for a trained policy).
"""

from __future__ import annotations

import dataclasses

import jax
import numpy as np

from kinetix_cli.env.actions import binding_values
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.episode import Policy, run_episode
from kinetix_cli.env.level import Level, to_host
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


def record_episode(
    env: KinetixEnv, params: EnvParams, level: Level, policy: Policy, key: jax.Array, horizon: int
) -> Episode:
    """Play one episode of `level` under `policy` and keep every state until it ends."""

    @jax.jit
    def play(level, key):
        return run_episode(env, params, level, policy, key, horizon, record=True)

    outcome, trace = to_host(play(level, key))
    length = int(outcome.length)
    start = jax.tree.map(lambda x: np.asarray(x)[None], level.physics)
    frames = jax.tree.map(lambda a, b: np.concatenate([a, b[:length]]), start, trace.physics)
    return Episode(
        physics=frames,
        bindings=to_host(level.bindings),
        action_type=env.action,
        actions=trace.action[:length],
        rewards=trace.reward[:length],
        solved=bool(outcome.solved),
        failed=bool(outcome.failed),
        length=length,
        step_seconds=env.frame_skip * float(level.engine_params.dt),
    )


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
