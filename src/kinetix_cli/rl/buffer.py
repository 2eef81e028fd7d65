"""The level buffer shared by the curricula: a fixed-capacity batch of levels with a score and a solve rate each.

Shapes are static (capacity, ...); `size` says how many slots, from the first, hold levels. Pure functions, all
jittable.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from flax import struct

from kinetix_cli.env.level import Level, index_level


@struct.dataclass
class LevelBuffer:
    """Levels a curriculum trains on.

    Attributes:
        levels: (capacity, ...) batched levels; slots at and after `size` hold placeholders.
        score: (capacity,) float32 the curriculum's priority (SFL: learnability p (1 - p); PLR: MaxMC or
            positive value loss).
        solve_rate: (capacity,) float32 the policy's solve rate p when the level was last played.
        size: () int32 filled slots.
        last_seen: (capacity,) int32 the update at which the level was last played (PLR's staleness).
        max_return: (capacity,) float32 the best episode return seen on the level (PLR's MaxMC score).
        rounds: () int32 scoring rounds so far: SFL refreshes, or PLR updates spent on new levels (no training).
    """

    levels: Level
    score: jax.Array
    solve_rate: jax.Array
    size: jax.Array
    last_seen: jax.Array
    max_return: jax.Array
    rounds: jax.Array


def empty_buffer(placeholder: Level, capacity: int) -> LevelBuffer:
    """A buffer of `capacity` slots, all empty; `placeholder` is a batch of one level giving the shapes."""
    return LevelBuffer(
        levels=jax.tree.map(lambda x: jnp.repeat(jnp.asarray(x)[:1], capacity, axis=0), placeholder),
        score=jnp.zeros(capacity, jnp.float32),
        solve_rate=jnp.zeros(capacity, jnp.float32),
        size=jnp.zeros((), jnp.int32),
        last_seen=jnp.zeros(capacity, jnp.int32),
        max_return=jnp.zeros(capacity, jnp.float32),
        rounds=jnp.zeros((), jnp.int32),
    )


def top_levels(
    levels: Level,
    score: jax.Array,
    solve_rate: jax.Array,
    capacity: int,
    last_seen: jax.Array,
    max_return: jax.Array,
    rounds: jax.Array,
) -> LevelBuffer:
    """A buffer of the `capacity` highest-scoring of a batch of levels (ties: the earlier level), best first;
    levels scoring -inf are left out (empty slots)."""
    _, best = jax.lax.top_k(score, capacity)
    return LevelBuffer(
        levels=index_level(levels, best),
        score=score[best],
        solve_rate=solve_rate[best],
        size=jnp.isfinite(score[best]).sum().astype(jnp.int32),
        last_seen=last_seen[best],
        max_return=max_return[best],
        rounds=jnp.asarray(rounds, jnp.int32),
    )


def draw_from_buffer(buffer: LevelBuffer, key: jax.Array, count: int) -> Level:
    """`count` levels drawn uniformly (with replacement) from the filled slots."""
    rows = jax.random.randint(key, (count,), 0, jnp.maximum(buffer.size, 1))
    return index_level(buffer.levels, rows)


@jax.jit
def buffer_metrics(buffer: LevelBuffer) -> dict[str, jax.Array]:
    """What a researcher needs to see a curriculum work: the buffer's size, mean score, and the distribution of
    its levels' solve rates (mean and the 10th, 50th and 90th percentiles). One program (a run logs it after every
    update; op by op, its first call compiled about ten small programs in every new process)."""
    filled = jnp.arange(buffer.score.shape[0]) < buffer.size
    count = jnp.maximum(buffer.size, 1)
    rates = jnp.where(filled, buffer.solve_rate, jnp.nan)
    p10, p50, p90 = jnp.where(buffer.size > 0, jnp.nanpercentile(rates, jnp.array([10.0, 50.0, 90.0])), 0.0)
    return {
        "buffer_size": buffer.size.astype(jnp.float32),
        "buffer_score": jnp.where(filled, buffer.score, 0.0).sum() / count,
        "buffer_solve_rate": jnp.where(filled, buffer.solve_rate, 0.0).sum() / count,
        "buffer_solve_p10": p10,
        "buffer_solve_p50": p50,
        "buffer_solve_p90": p90,
    }
