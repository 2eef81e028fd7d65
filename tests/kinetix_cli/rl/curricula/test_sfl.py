"""SFL: scoring plays the policy on candidate levels, the buffer holds the most learnable, training mixes them in,
and a resumed SFL run ends bit-identical to an uninterrupted one."""

from __future__ import annotations

import json
import shutil

import jax
import numpy as np
import pytest

from helpers.cli import kinetix
from helpers.pages import read_report
from helpers.runs import SFL, SFL_RUN_GROUP, sfl_config, tiny_config
from kinetix_cli.env.factory import make_env
from kinetix_cli.rl.curricula import make_curriculum
from kinetix_cli.rl.curricula.sfl import episode_counts, refresh_buffer
from kinetix_cli.rl.networks import make_network
from kinetix_cli.rl.pool import fresh_source, level_pool
from kinetix_cli.rl.ppo import init_runner
from kinetix_cli.rl.train import train

pytestmark = SFL_RUN_GROUP


def lines(run_dir):
    return [{k: v for k, v in json.loads(x).items() if k != "sps"} for x in (run_dir / "metrics.jsonl").open()]


def test_an_sfl_run_logs_its_buffer_resumes_bit_identically_and_draws_it(capsys, tmp_path, sfl_run):
    whole, run_dir = sfl_run
    records = lines(run_dir)
    assert len(records) == 300
    assert [r["scoring_steps"] for r in records] == [256 * ((u + 1) // 2) for u in range(1, 301)]  # before odd updates
    # 8 levels x 2 attempts x 16 steps
    assert records[0]["scoring_share"] == pytest.approx(256 / (256 + 64), abs=1e-6)  # [share of steps, 0-1]
    assert all(r["buffer_size"] == 4 and 0 <= r["buffer_score"] <= 0.25 for r in records)
    assert all(r["buffer_solve_p10"] <= r["buffer_solve_p50"] <= r["buffer_solve_p90"] for r in records)
    scores = np.asarray(whole.buffer.score)
    # [score, 0-0.25]: p (1 - p) in float32, a few ulps of 0.25
    np.testing.assert_allclose(scores, whole.buffer.solve_rate * (1 - whole.buffer.solve_rate), rtol=1e-6, atol=1e-7)
    assert (np.diff(scores) <= 0).all(), "best first"

    # The run as a kill before its last checkpoint leaves it: checkpoints 148 and 296, every metrics line written
    assert sorted(p.name for p in (run_dir / "checkpoints").iterdir()) == ["148", "296", "300"]
    cut = tmp_path / "cut"
    shutil.copytree(run_dir, cut)
    shutil.rmtree(cut / "checkpoints" / "300")
    config, pool = sfl_config(), level_pool(sfl_config())
    resumed = train(config, cut, resume=True, pool=pool)  # from checkpoint 296, buffer included
    jax.tree.map(np.testing.assert_array_equal, whole.params, resumed.params)
    jax.tree.map(np.testing.assert_array_equal, whole.buffer, resumed.buffer)
    assert lines(tmp_path / "cut") == records

    sheet = tmp_path / "buffer.png"
    result = kinetix(capsys, "levels", "show", run_dir, "--buffer", "--grid", "4", "-o", sheet)
    assert result.code == 0 and "4 buffer levels" in result.out and sheet.read_bytes()[:4] == b"\x89PNG"


def test_the_report_of_an_sfl_run_shows_its_buffer(capsys, tmp_path, sfl_run):
    _, run_dir = sfl_run
    result = kinetix(capsys, "report", run_dir, "-o", tmp_path / "report")
    page, payload = read_report(tmp_path / "report")
    assert result.code == 0 and payload["levels"] == []  # the run evaluates nothing (run.eval_every=0)
    assert payload["buffers"] == [{"run": str(run_dir), "image": "buffers/0.png", "levels": 4}]
    assert "buffers/0.png" in page.refs and "No evaluation" in " ".join(page.text)


def test_scoring_counts_the_episodes_of_every_copy_of_a_level(tiny_pool):
    config = tiny_config("env.max_steps=4")  # every episode ends within 4 steps: at least 2 per copy in 8 steps
    env, env_params = make_env(config.env)
    network = make_network(config.model, config.env)
    runner = init_runner(env, network, config.ppo, tiny_pool, jax.random.key(0))
    count = jax.jit(episode_counts, static_argnames=("env", "network", "steps", "attempts"))
    keys = jax.random.split(jax.random.key(1), 2 * 3)
    solved, ended = count(runner.params, env_params, tiny_pool, keys, env=env, network=network, steps=8, attempts=3)
    solved, ended = np.asarray(solved), np.asarray(ended)
    assert solved.shape == ended.shape == (2,)  # one count per level, the 3 copies summed
    assert (ended >= 2 * 3).all() and (ended <= 8 * 3).all()  # one copy alone ends 2 to 8 episodes
    assert (solved >= 0).all() and (solved <= ended).all()


def test_a_refresh_plays_all_its_batches_at_once_on_the_levels_and_keys_each_batch_draws():
    # 2 batches of 4 fresh candidates, 2 copies each, 64 steps: enough for some of them to be solved
    config = tiny_config(
        *SFL, "levels.source=fresh", "levels.files=[]", "curriculum.score_steps=64", "curriculum.buffer_size=8"
    )
    settings, fresh = config.curriculum, fresh_source(config)
    env, env_params = make_env(config.env)
    network = make_network(config.model, config.env)
    runner = init_runner(env, network, config.ppo, None, jax.random.key(0), fresh=fresh, buffer_size=8)
    parts = {"env": env, "network": network, "fresh": fresh, "curriculum": settings}
    key = jax.random.key(3)
    buffer = refresh_buffer(runner.params, env_params, None, key, **parts, buffer=runner.buffer, update=0)

    count = jax.jit(episode_counts, static_argnames=("env", "network", "steps", "attempts"))
    expected = {}
    for k in jax.random.split(key, 2):  # each batch alone, as scoring ran before it was one call
        k_levels, k_play = jax.random.split(k)
        levels = jax.jit(fresh, static_argnums=1)(k_levels, 4)
        keys = jax.random.split(k_play, 4 * 2)
        kw = {"env": env, "network": network, "steps": settings.score_steps, "attempts": 2}
        solved, ended = count(runner.params, env_params, levels, keys, **kw)
        for i, rate in enumerate(np.asarray(solved / np.maximum(ended, 1.0))):
            expected[level_bytes(levels, i)] = rate
    assert len(expected) == 8 and len(set(expected.values())) > 1  # 8 distinct levels, rates that tell them apart
    got = {level_bytes(buffer.levels, i): rate for i, rate in enumerate(np.asarray(buffer.solve_rate))}
    assert got == expected


def level_bytes(levels, i: int) -> bytes:
    """Level `i` of a batch as bytes: equal for equal levels."""
    return b"".join(np.asarray(leaf[i]).tobytes() for leaf in jax.tree.leaves(levels))


def test_a_refresh_loads_the_update_beside_it_and_the_update_compiles_nothing():
    """A process's first refresh compiles (or reads from the compile cache) the update's program beside its own
    (`trace_cache.compiling`): the refreshed runner's buffer has the types of the one it replaces, so the update
    that follows finds its program compiled. Sizes of this test alone: no other test compiled these programs."""
    compiles = []  # compiles and compile-cache reads (jax's monitoring events)
    jax.monitoring.register_event_listener(lambda event, **_: compiles.append(event) if "requests" in event else None)
    jax.monitoring.register_event_duration_secs_listener(
        lambda event, seconds, **_: compiles.append(event) if event.endswith("backend_compile_duration") else None
    )
    config = tiny_config(*SFL, "levels.source=fresh", "levels.files=[]", "curriculum.score_steps=24")
    fresh = fresh_source(config)
    env, env_params = make_env(config.env)
    network = make_network(config.model, config.env)
    sfl = make_curriculum(config.curriculum, env=env, network=network, ppo=config.ppo, fresh=fresh)
    runner = init_runner(env, network, config.ppo, None, jax.random.key(0), fresh=fresh, buffer_size=sfl.buffer_size)
    runner = jax.block_until_ready(sfl.before_update(runner, env_params, None, jax.random.key(1), 0))
    refreshed = len(compiles)
    runner, metrics = sfl.update(runner, env_params, None)
    assert len(compiles) == refreshed and np.isfinite(float(metrics["loss"]))
