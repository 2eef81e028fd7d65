"""Robust PLR, prioritised level replay (Jiang et al., 2021), as the Kinetix paper runs it: the update itself is
`rl.ppo.plr_update`; here are the buffer's replay distribution, the level scores and the buffer updates.

Every update resets all environments. With probability `replay_prob` (once the buffer is `min_fill` full) they
replay levels sampled from the buffer, train on them and rescore them; otherwise they play new levels from the
source, which are scored but not trained on (the "robust" variant: gradients only from curated levels), and the
best-scoring of buffer and new levels stay. A level's replay probability mixes its score rank and its staleness:
P = (1 - staleness) P_rank + staleness P_stale, with P_rank proportional to rank^(-1/temperature) and P_stale to the
updates since it was last played.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from kinetix_cli.config import CurriculumSettings
from kinetix_cli.env.level import Level
from kinetix_cli.rl.curricula.buffer import LevelBuffer, top_levels


def replay_probabilities(buffer: LevelBuffer, update: jax.Array, curriculum: CurriculumSettings) -> jax.Array:
    """(capacity,) float32 probability of replaying each slot (0 for empty slots; sums to 1 when any is filled)."""
    capacity = buffer.score.shape[0]
    filled = jnp.arange(capacity) < buffer.size
    order = jnp.argsort(jnp.where(filled, -buffer.score, jnp.inf))  # best first, empty slots last
    rank = jnp.zeros(capacity, jnp.float32).at[order].set(jnp.arange(1, capacity + 1, dtype=jnp.float32))
    by_rank = jnp.where(filled, rank ** (-1.0 / curriculum.temperature), 0.0)
    stale = jnp.where(filled, (update - buffer.last_seen).astype(jnp.float32), 0.0)
    by_rank = by_rank / jnp.maximum(by_rank.sum(), 1e-30)
    stale = stale / jnp.maximum(stale.sum(), 1e-30)
    mixed = (1.0 - curriculum.staleness) * by_rank + curriculum.staleness * stale
    return mixed / jnp.maximum(mixed.sum(), 1e-30)


def sample_replay(
    buffer: LevelBuffer, key: jax.Array, count: int, update: jax.Array, curriculum: CurriculumSettings
) -> jax.Array:
    """(count,) int32 buffer slots to replay, drawn with replacement from `replay_probabilities`."""
    probabilities = replay_probabilities(buffer, update, curriculum)
    return jax.random.choice(key, probabilities.shape[0], (count,), p=probabilities)


def level_scores(
    value: jax.Array,
    advantages: jax.Array,
    finished_return: jax.Array,
    done: jax.Array,
    solved: jax.Array,
    best_before: jax.Array,
    curriculum: CurriculumSettings,
) -> tuple[jax.Array, jax.Array, jax.Array]:
    """(score, solve rate, best return), each (num_envs,), of the level each environment played for the whole
    rollout. Inputs are (num_steps, num_envs): value estimates, GAE advantages, returns of episodes that ended
    (0 elsewhere), done and solved flags; `best_before` is the best return known before (-inf for a new level).

    MaxMC: mean over steps of (best return - value); PVL: mean over steps of max(advantage, 0)."""
    ended = done.sum(0)
    best = jnp.maximum(best_before, jnp.where(done > 0, finished_return, -jnp.inf).max(0))
    best = jnp.where(jnp.isfinite(best), best, value.max(0))  # no episode ended: nothing better than the values
    maxmc = (best[None] - value).mean(0)
    pvl = jnp.maximum(advantages, 0.0).mean(0)
    score = maxmc if curriculum.plr_score == "maxmc" else pvl
    return score, solved.sum(0) / jnp.maximum(ended, 1.0), best


def rescore(
    buffer: LevelBuffer, slots: jax.Array, score: jax.Array, solve_rate: jax.Array, best: jax.Array, update
) -> LevelBuffer:
    """The buffer with the replayed `slots` given their new score, solve rate and best return, seen at `update`."""
    return buffer.replace(
        score=buffer.score.at[slots].set(score),
        solve_rate=buffer.solve_rate.at[slots].set(solve_rate),
        max_return=buffer.max_return.at[slots].set(best),
        last_seen=buffer.last_seen.at[slots].set(jnp.asarray(update, jnp.int32)),
    )


def insert(
    buffer: LevelBuffer, levels: Level, score: jax.Array, solve_rate: jax.Array, best: jax.Array, update
) -> LevelBuffer:
    """The buffer after new `levels` were scored: the best-scoring of its levels and the new ones, best first
    (new levels fill empty slots first, then replace lower scores); one more scoring round."""
    capacity = buffer.score.shape[0]
    filled = jnp.arange(capacity) < buffer.size
    join = lambda a, b: jnp.concatenate([a, b])  # noqa: E731
    return top_levels(
        jax.tree.map(join, buffer.levels, levels),
        join(jnp.where(filled, buffer.score, -jnp.inf), score),
        join(buffer.solve_rate, solve_rate),
        capacity,
        join(buffer.last_seen, jnp.full(score.shape, update, jnp.int32)),
        join(buffer.max_return, best),
        buffer.rounds + 1,
    )
