"""Robust PLR and ACCEL: the replay distribution (rank and staleness), the MaxMC and PVL scores, the buffer's
rescoring and insertion, and PLR and ACCEL runs that train only on replays (ACCEL also scores mutations) and resume
bit-identically."""

from __future__ import annotations

import dataclasses
import functools
import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from helpers.runs import tiny_config
from kinetix_cli.config import ConfigError, CurriculumSettings
from kinetix_cli.rl.buffer import empty_buffer
from kinetix_cli.rl.curricula import plr
from kinetix_cli.rl.train import train

PLR = [
    "curriculum.name=plr",
    "curriculum.buffer_size=8",
    "curriculum.min_fill=0.5",
    "env.max_steps=8",  # the tiny run's rollouts are 8 steps: whole episodes
    "run.eval_every=0",
]


# Jitted: op by op, each of a level's ~50 arrays costs its own small compile (~40 ms each here).
empty = jax.jit(empty_buffer, static_argnums=1)
insert, rescore = jax.jit(plr.insert), jax.jit(plr.rescore)
replay_probabilities = jax.jit(plr.replay_probabilities, static_argnums=2)
sample_replay = jax.jit(plr.sample_replay, static_argnums=(2, 4))


@functools.partial(jax.jit, static_argnums=3)
def buffer_of(tiny_pool, scores, seen, capacity=6):
    buffer = empty_buffer(tiny_pool, capacity)
    n = len(scores)
    return buffer.replace(
        score=buffer.score.at[:n].set(scores),
        last_seen=buffer.last_seen.at[:n].set(seen),
        size=jnp.asarray(n, jnp.int32),
    )


def test_replay_mixes_score_rank_and_staleness_over_filled_slots(tiny_pool):
    buffer = buffer_of(tiny_pool, jnp.array([0.1, 0.4, 0.2, 0.3]), jnp.array([9, 8, 5, 10]))  # ranks 4, 1, 3, 2
    by_rank = CurriculumSettings(name="plr", staleness=0.0, temperature=0.5)
    p = np.asarray(replay_probabilities(buffer, jnp.asarray(10), by_rank))
    h = np.array([4.0, 1.0, 3.0, 2.0]) ** -2.0
    np.testing.assert_allclose(p, [*(h / h.sum()), 0, 0], rtol=1e-5, atol=1e-7)  # [probability]
    by_age = dataclasses.replace(by_rank, staleness=1.0)
    p = np.asarray(replay_probabilities(buffer, jnp.asarray(10), by_age))
    np.testing.assert_allclose(p, [1 / 8, 2 / 8, 5 / 8, 0, 0, 0], rtol=1e-5, atol=1e-7)  # [probability]
    slots = np.asarray(sample_replay(buffer, jax.random.key(0), 512, jnp.asarray(10), by_age))
    assert set(slots) == {0, 1, 2} and (slots == 2).mean() > 0.5


def test_maxmc_and_pvl_scores():
    value = jnp.array([[0.5, 0.0], [0.3, 0.2]])  # (steps, envs)
    advantages = jnp.array([[0.2, -0.1], [-0.3, 0.4]])
    finished = jnp.array([[0.0, 0.0], [0.9, 0.0]])
    done = jnp.array([[0.0, 0.0], [1.0, 0.0]])
    solved = jnp.array([[0.0, 0.0], [1.0, 0.0]])
    before = jnp.array([-jnp.inf, 1.5])
    maxmc = CurriculumSettings(name="plr", plr_score="maxmc")
    score, rate, best = plr.level_scores(value, advantages, finished, done, solved, before, maxmc)
    np.testing.assert_allclose(best, [0.9, 1.5], atol=1e-6)  # [return]
    np.testing.assert_allclose(score, [(0.4 + 0.6) / 2, (1.5 + 1.3) / 2], rtol=1e-6, atol=1e-6)  # [return]
    np.testing.assert_allclose(rate, [1.0, 0.0], atol=1e-7)  # [solve rate, 0-1]
    pvl = dataclasses.replace(maxmc, plr_score="pvl")
    pvl_score = plr.level_scores(value, advantages, finished, done, solved, before, pvl)[0]
    np.testing.assert_allclose(pvl_score, [0.1, 0.2], atol=1e-6)  # [return]


def test_insert_fills_empty_slots_then_replaces_lower_scores_and_rescore_updates_in_place(tiny_pool):
    buffer = buffer_of(tiny_pool, jnp.array([0.5, 0.1]), jnp.array([1, 1]), 3)
    levels = jax.jit(lambda pool: jax.tree.map(lambda x: jnp.concatenate([x, x]), pool))(tiny_pool)  # 4 new levels
    scores = jnp.array([0.3, 0.05, 0.7, 0.2])
    zeros = jnp.zeros(4)
    inserted = insert(buffer, levels, scores, zeros, zeros, 4)
    np.testing.assert_allclose(inserted.score, [0.7, 0.5, 0.3], atol=1e-7)  # [score]: float32 copies
    np.testing.assert_array_equal(inserted.last_seen, [4, 1, 4])
    assert int(inserted.size) == 3 and int(inserted.rounds) == 1
    few = insert(empty(tiny_pool, 8), levels, scores, zeros, zeros, 0)
    assert int(few.size) == 4 and np.isneginf(np.asarray(few.score)[4:]).all()

    rescored = rescore(inserted, jnp.array([2, 0]), jnp.array([0.9, 0.1]), jnp.ones(2), jnp.ones(2), 6)
    np.testing.assert_allclose(rescored.score, [0.1, 0.5, 0.9], atol=1e-7)  # [score]: float32 copies
    np.testing.assert_array_equal(rescored.last_seen, [6, 1, 6])
    assert int(rescored.rounds) == 1


def lines(run_dir):
    return [{k: v for k, v in json.loads(x).items() if k != "sps"} for x in (run_dir / "metrics.jsonl").open()]


def test_the_round_waits_for_min_fill_then_follows_the_replay_probability(tiny_pool):
    """`plr_round`: new levels until the buffer is `min_fill` full; then PLR replays with probability p and ACCEL
    picks replay, mutation and new levels with probabilities p, p and 1 - p over 1 + p (here 1/6, 1/6, 2/3)."""
    keys = jax.random.split(jax.random.key(0), 3000)

    def shares(buffer, accel, p):
        curriculum = CurriculumSettings(name="accel" if accel else "plr", min_fill=0.5, replay_prob=p)
        runner = plr.Runner(None, None, None, None, jnp.zeros(1), keys[0], jnp.int32(0), buffer)
        pick = lambda key: plr.plr_round(runner.replace(key=key), curriculum=curriculum, accel=accel)  # noqa: E731
        rounds = np.asarray(jax.vmap(pick)(keys))
        return [float((rounds == i).mean()) for i in range(len(plr.ROUNDS))]  # replay, mutate, new

    filling = buffer_of(tiny_pool, jnp.array([0.1, 0.4]), jnp.array([0, 0]))  # 2 of 6 slots: under half full
    ready = buffer_of(tiny_pool, jnp.array([0.1, 0.4, 0.2]), jnp.array([0, 0, 0]))
    assert shares(filling, True, 0.5) == [0.0, 0.0, 1.0]
    np.testing.assert_allclose(shares(ready, False, 0.5), [0.5, 0.0, 0.5], atol=0.03)  # [share]: 3 sd of 3000 draws
    np.testing.assert_allclose(shares(ready, True, 0.2), [1 / 6, 1 / 6, 2 / 3], atol=0.03)


class Crash(Exception):
    pass


def test_a_round_that_trained_nothing_is_logged_without_losses():
    trained = {"replay": 1.0, "mutate": 0.0, "solve_rate": 0.5, "loss": 0.1, "entropy": 1.2, "approx_kl": 0.01}
    scored = trained | {"replay": 0.0, "loss": 0.0, "entropy": 0.0, "approx_kl": 0.0}
    curriculum = plr.PLR(None, None, None, None, CurriculumSettings(name="plr"))  # logging needs no environment
    assert curriculum.logged(trained) == trained
    assert curriculum.logged(scored) == {"replay": 0.0, "mutate": 0.0, "solve_rate": 0.5}  # no entropy of 0 in curves


# make test-all: a PLR run compiles ~40 s (make test stays under 8 minutes); the replay, scores and insert logic are
# tested above, and an SFL run trains and resumes in make test (test_sfl)
@pytest.mark.slow
@pytest.mark.parametrize("name", ["plr", "accel"])
def test_a_plr_run_trains_only_on_replays_and_resumes_bit_identically(tmp_path, tiny_pool, name):
    config = tiny_config(*PLR, "ppo.total_timesteps=1280", f"curriculum.name={name}", "curriculum.edits=2")
    whole = train(config, tmp_path / "whole", pool=tiny_pool)  # 20 updates
    records = lines(tmp_path / "whole")
    replays = [r["replay"] for r in records]
    assert replays[:1] == [0.0] and 1.0 in replays, replays  # the buffer fills before the first replay
    mutations = [r["mutate"] for r in records]
    assert (1.0 in mutations) == (name == "accel") and not any(r["replay"] and r["mutate"] for r in records)
    for r in records:
        assert ("loss" in r and r["loss"] != 0.0) == (r["replay"] == 1.0)  # new levels are scored, not trained on
        assert r["scoring_steps"] == 64 * sum(1 - x["replay"] for x in records if x["update"] <= r["update"])
        assert r["total_steps"] == r["steps"] and r["scoring_share"] == r["scoring_steps"] / r["steps"]
    assert records[-1]["buffer_size"] == 8
    if name == "accel":
        return  # the resume path is PLR's; mutations are functions of the runner's key, which the checkpoint holds

    def crash_after_13(record):
        if record["update"] == 13:
            raise Crash

    with pytest.raises(Crash):
        train(config, tmp_path / "cut", pool=tiny_pool, progress=crash_after_13)
    resumed = train(config, tmp_path / "cut", resume=True, pool=tiny_pool)
    jax.tree.map(np.testing.assert_array_equal, whole.params, resumed.params)
    jax.tree.map(np.testing.assert_array_equal, whole.buffer, resumed.buffer)
    assert lines(tmp_path / "cut") == records


def test_plr_needs_whole_episodes_in_a_rollout():
    with pytest.raises(ConfigError, match="ppo.num_steps: 8 is shorter than env.max_steps 256"):
        tiny_config("curriculum.name=plr", "env.max_steps=256")
