"""The level buffer: top levels by score, uniform draws from the filled slots, and its metrics."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from kinetix_cli.env.level import level_count
from kinetix_cli.rl import buffer as buffers

# Jitted: op by op, each of a level's ~50 arrays costs its own small compile (~40 ms each here).
top_levels = jax.jit(buffers.top_levels, static_argnums=3)
empty_buffer = jax.jit(buffers.empty_buffer, static_argnums=1)
draw_from_buffer = jax.jit(buffers.draw_from_buffer, static_argnums=2)
buffer_metrics = buffers.buffer_metrics


@jax.jit
def six_levels(pool):
    """The two pool levels three times each, made distinguishable by their bodies' positions."""
    levels = jax.tree.map(lambda x: jnp.concatenate([x, x, x]), pool)
    bodies = levels.physics.bodies
    shifted = bodies.position + jnp.arange(6.0)[:, None, None] * 0.01
    return levels.replace(physics=levels.physics.replace(bodies=bodies.replace(position=shifted)))


def test_top_levels_keeps_the_best_first_and_draws_only_filled_slots(tiny_pool):
    levels = six_levels(tiny_pool)
    score = jnp.array([0.1, 0.25, 0.0, 0.2, 0.16, 0.05])
    rate = jnp.array([0.9, 0.5, 1.0, 0.3, 0.2, 0.05])
    seen, best = jnp.arange(6, dtype=jnp.int32), jnp.arange(6.0) / 10
    buffer = top_levels(levels, score, rate, 3, seen, best, jnp.asarray(7))
    np.testing.assert_allclose(buffer.score, [0.25, 0.2, 0.16], atol=1e-7)  # [score]: float32 copies
    np.testing.assert_allclose(buffer.solve_rate, [0.5, 0.3, 0.2], atol=1e-7)  # [solve rate, 0-1]
    np.testing.assert_array_equal(buffer.last_seen, [1, 3, 4])
    np.testing.assert_allclose(buffer.max_return, [0.1, 0.3, 0.4], atol=1e-7)  # [return]
    assert int(buffer.rounds) == 7 and int(buffer.size) == 3
    expected = np.asarray(levels.physics.bodies.position)[[1, 3, 4]]
    np.testing.assert_array_equal(buffer.levels.physics.bodies.position, expected)

    metrics = jax.device_get(buffer_metrics(buffer))
    assert metrics["buffer_size"] == 3 and np.isclose(metrics["buffer_score"], 0.61 / 3)
    assert np.isclose(metrics["buffer_solve_p50"], 0.3) and np.isclose(metrics["buffer_solve_rate"], 1.0 / 3)

    empty = empty_buffer(tiny_pool, 8)
    assert level_count(empty.levels) == 8 and int(empty.size) == 0
    assert all(np.isfinite(v) for v in jax.device_get(buffer_metrics(empty)).values())
    fill = jax.jit(lambda b, t: jax.tree.map(lambda b, t: b.at[:3].set(t), b, t))
    partly = empty.replace(levels=fill(empty.levels, buffer.levels), size=3)
    drawn = draw_from_buffer(partly, jax.random.key(0), 64)
    filled = {row.tobytes() for row in np.asarray(buffer.levels.physics.bodies.position)}
    assert {row.tobytes() for row in np.asarray(drawn.physics.bodies.position)} == filled
