"""Recorded episodes (`record_episodes`): several levels in one batched rollout, each episode its own level's,
cut at its own end, with the start state first."""

from __future__ import annotations

import jax
import numpy as np

from helpers.paths import LEVELS
from kinetix_cli.env.actions import sample_action
from kinetix_cli.env.factory import make_env
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.solution import SOLUTION_SETTINGS
from kinetix_cli.viz.rollout import record_episodes


def test_a_batch_of_levels_gives_each_level_its_own_episode():
    # [A, B, B, A] with keys [a, b, b, a] in one call (one compile): episodes 0 and 3, and 1 and 2, must be equal,
    # so the batch's episodes are split by level index, not mixed up
    specs = [load_level(LEVELS / "s" / name) for name in ("rocket-car-jump.json", "pad-to-pad.json")]
    env, params = make_env(SOLUTION_SETTINGS, specs[0].default_static())
    levels = [spec.build(env.static) for spec in specs]
    a, b = jax.random.split(jax.random.key(3))
    policy = lambda key, obs, t: sample_action(env.action, key)  # noqa: E731
    episodes = record_episodes(
        env, params, [levels[0], levels[1], levels[1], levels[0]], policy, jax.numpy.stack([a, b, b, a]), 64
    )
    for i, j in ((0, 3), (1, 2)):
        assert episodes[i].length == episodes[j].length and episodes[i].solved == episodes[j].solved
        np.testing.assert_array_equal(episodes[i].rewards, episodes[j].rewards)
        jax.tree.map(np.testing.assert_array_equal, episodes[i].physics, episodes[j].physics)
    for episode, level in zip(episodes, [levels[0], levels[1], levels[1], levels[0]], strict=True):
        start = jax.tree.map(lambda x: x[0], episode.physics)
        jax.tree.map(np.testing.assert_array_equal, start, jax.tree.map(np.asarray, level.physics))
        assert len(episode.rewards) == len(episode.actions) == episode.length
        assert jax.tree.leaves(episode.physics)[0].shape[0] == episode.length + 1
    assert not np.array_equal(episodes[0].physics.bodies.position[1], episodes[1].physics.bodies.position[1])
