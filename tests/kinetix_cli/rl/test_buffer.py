"""The level buffer: top levels by score, uniform draws from the filled slots, and its metrics."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from kinetix_cli.env.level import level_count
from kinetix_cli.rl.buffer import buffer_metrics, draw_from_buffer, empty_buffer, top_levels


def test_top_levels_keeps_the_best_first_and_draws_only_filled_slots(tiny_pool):
    levels = jax.tree.map(lambda x: jnp.concatenate([x, x, x]), tiny_pool)  # 6 levels, made distinguishable:
    bodies = levels.physics.bodies
    shifted = bodies.position + jnp.arange(6.0)[:, None, None] * 0.01
    levels = levels.replace(physics=levels.physics.replace(bodies=bodies.replace(position=shifted)))
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
    partly = empty.replace(levels=jax.tree.map(lambda b, t: b.at[:3].set(t), empty.levels, buffer.levels), size=3)
    drawn = draw_from_buffer(partly, jax.random.key(0), 64)
    filled = {row.tobytes() for row in np.asarray(buffer.levels.physics.bodies.position)}
    assert {row.tobytes() for row in np.asarray(drawn.physics.bodies.position)} == filled
