"""Behaviour cloning of solved levels: the replayed demonstrations are the solutions' own episodes, cloning steps
make the stored actions the policy's, a bad solved set is one clear line, and a run clones before PPO and beside
it, resumably, its cloning time counted in a resumed run's budget."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import jax
import numpy as np
import optax
import pytest

from helpers.levelsets import small_levelset, solved_levelset
from helpers.paths import LEVELS, REPO
from helpers.processes import TIMEOUT, release_env
from helpers.runs import tiny_config
from helpers.traces import traces
from kinetix_cli.config import ConfigError
from kinetix_cli.errors import UserError
from kinetix_cli.parallel import make_mesh
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.clone import Cloning, clone_step, demonstration_env, load_demonstrations, replay_observations
from kinetix_cli.rl.networks import make_network, training_network
from kinetix_cli.rl.pool import level_pool
from kinetix_cli.rl.train import train

FILES = [LEVELS / "s" / "rocket-car-jump.json", LEVELS / "s" / "pad-to-pad.json", LEVELS / "s" / "jet-ball-hop.json"]
CLONE = ["env.frame_skip=2"]  # solutions are played at the default frame skip; the tiny run's is 4


@pytest.fixture(scope="module")
def solved_set(tmp_path_factory):
    """Three shipped s levels with their solutions, the last marked unsolved."""
    out = tmp_path_factory.mktemp("solved") / "set"
    solved_levelset(out, FILES, unsolved=1)
    return out


def clone_config(solved_set, *overrides):
    return tiny_config(*CLONE, f"clone.levels={solved_set}", *overrides)


def test_demonstrations_are_the_solved_levels_replayed_with_their_actions(solved_set):
    demos, size = load_demonstrations(clone_config(solved_set, "clone.updates=1"))
    assert size == "s" and demos.length.shape == (2,)  # the unsolved level is left out
    env, params = demonstration_env(clone_config(solved_set, "clone.updates=1"), size)
    replay = jax.jit(replay_observations, static_argnums=(0, 4))  # op by op: ~80 small compiles
    observations, actions, valid = replay(env, params, demos, jax.random.key(0), 8)
    rows = [int(np.flatnonzero((demos.actions == np.swapaxes(actions, 0, 1)[i]).all((1, 2)))[0]) for i in range(8)]
    np.testing.assert_array_equal(valid.sum(0), np.asarray(demos.length)[rows])  # the steps before each solve
    starts = jax.jit(lambda levels, rows: jax.vmap(env.initial_state)(jax.tree.map(lambda x: x[rows], levels)))
    first = jax.vmap(env.observe)(starts(demos.levels, np.asarray(rows)))
    jax.tree.map(lambda a, b: np.testing.assert_allclose(a[0], b, rtol=0, atol=1e-6), observations, first)


@pytest.mark.slow  # ~32 s: cloning steps compile and run; make test keeps the demonstrations and the one-line error
def test_cloning_steps_make_the_stored_actions_likely(solved_set):
    config = clone_config(solved_set, "clone.updates=1")
    demos, size = load_demonstrations(config)
    env, params = demonstration_env(config, size)
    network = make_network(config.model, config.env)
    observations, _, _ = replay_observations(env, params, demos, jax.random.key(0), 2)
    weights = jax.jit(network.init)(jax.random.key(1), jax.tree.map(lambda x: x[0], observations))
    optimizer = optax.adam(3e-3)
    state, losses = optimizer.init(weights), []
    for step in range(40):
        key = jax.random.key(step)
        weights, state, metrics = clone_step(
            weights, state, params, demos, key, env=env, network=network, optimizer=optimizer, count=4
        )
        losses.append(float(metrics["clone_loss"]))
    assert losses[-1] < 0.5 * losses[0], losses  # the negative log-likelihood of the solutions falls


def test_a_set_that_cannot_be_cloned_is_one_clear_line(solved_set, tmp_path):
    with pytest.raises(ConfigError, match="clone.updates: needs clone.levels"):
        tiny_config("clone.updates=3")
    with pytest.raises(ConfigError, match="clone.levels: is unused unless"):
        tiny_config(f"clone.levels={solved_set}")
    with pytest.raises(UserError, match="clone.levels: solutions are played with env.frame_skip 2; this run has 4"):
        load_demonstrations(tiny_config(f"clone.levels={solved_set}", "clone.updates=1"))
    small_levelset(tmp_path / "plain")
    with pytest.raises(UserError, match="holds no solutions; write a solved set with kinetix levels solve"):
        load_demonstrations(clone_config(tmp_path / "plain", "clone.updates=1"))
    solved_levelset(tmp_path / "none", FILES[:1], unsolved=1)
    with pytest.raises(UserError, match="no level of the set is solved"):
        load_demonstrations(clone_config(tmp_path / "none", "clone.updates=1"))


class Crash(Exception):
    pass


@pytest.mark.slow
def test_a_run_clones_before_and_beside_ppo_and_resumes_bit_for_bit(solved_set, tmp_path):
    config = clone_config(solved_set, "clone.updates=3", "clone.coef=0.5", "clone.batch=2")
    pool = level_pool(config)
    whole = train(config, tmp_path / "whole", pool=pool)
    records = [json.loads(line) for line in (tmp_path / "whole" / "clone.jsonl").read_text().splitlines()]
    assert [r["clone_step"] for r in records] == [1, 2, 3] and all(r["seconds"] > 0 for r in records)
    lines = [json.loads(line) for line in (tmp_path / "whole" / "metrics.jsonl").read_text().splitlines()]
    assert all(np.isfinite(line["clone_loss"]) for line in lines) and len(lines) == 6

    def crash_after_3(record):
        if record.get("update") == 3:
            raise Crash

    with pytest.raises(Crash):
        train(config, tmp_path / "cut", pool=pool, progress=crash_after_3)
    for copy in ("kept", "spent"):
        shutil.copytree(tmp_path / "cut", tmp_path / copy)
    budget = clone_config(solved_set, "clone.updates=3", "clone.coef=0.5", "clone.batch=2", "run.minutes=40")
    train(budget, tmp_path / "kept", resume=True, pool=pool)  # 40 minutes: the resumed run trains on
    assert len((tmp_path / "kept" / "metrics.jsonl").read_text().splitlines()) == 6
    log = tmp_path / "spent" / "clone.jsonl"  # cloning logged 3 x 1,000 s: a resumed run counts it in run.minutes
    log.write_text(
        "".join(json.dumps(json.loads(line) | {"seconds": 1000.0}) + "\n" for line in log.read_text().splitlines())
    )
    train(budget, tmp_path / "spent", resume=True, pool=pool)
    updates = [json.loads(line)["update"] for line in (tmp_path / "spent" / "metrics.jsonl").read_text().splitlines()]
    assert updates == [1, 2]  # the checkpoint's updates, none trained after
    resumed = train(config, tmp_path / "cut", resume=True, pool=pool)
    jax.tree.map(np.testing.assert_array_equal, whole.params, resumed.params)
    jax.tree.map(np.testing.assert_array_equal, load_policy(tmp_path / "whole").params, whole.params)
    cloning = Cloning(config, *load_demonstrations(config), make_mesh(None), make_network(config.model, config.env))
    cloning.beside_ppo(whole, jax.random.key(0))
    with traces() as traced:  # every update's cloning step shares one compile
        cloning.beside_ppo(whole, jax.random.key(1))
    assert traced[0] == 0
    plain = train(tiny_config(*CLONE), tmp_path / "plain", pool=pool)  # cloning changed the parameters
    pairs = zip(jax.tree.leaves(plain.params), jax.tree.leaves(whole.params), strict=True)
    assert any(not np.array_equal(a, b) for a, b in pairs)


FIRST_VIEW = """
import sys, jax, numpy as np
from helpers.runs import tiny_config
from kinetix_cli.rl.clone import demonstration_env, load_demonstrations, replay_observations
config = lambda *more: tiny_config("env.frame_skip=2", f"clone.levels={sys.argv[1]}", *more)
replays = []
for settings in (["clone.updates=2", "clone.coef=0.5", "clone.batch=2", "ppo.mirror_coef=1.0"], ["clone.updates=1"]):
    demos, size = load_demonstrations(config(*settings))
    env, params = demonstration_env(config(*settings), size)
    replays.append(jax.jit(replay_observations, static_argnums=(0, 4))(env, params, demos, jax.random.key(0), 2)[0])
(first, mirrored), plain = replays
same = lambda a, b: all(np.array_equal(x, y) for x, y in zip(jax.tree.leaves(a), jax.tree.leaves(b), strict=True))
print("equal" if same(first, plain) else "different", "same" if same(first, mirrored) else "mirrored")
"""
"""The first view of a mirrored replay against the plain replay, in a process compiled as `kinetix` compiles."""


@pytest.mark.slow  # the PPO update and cloning step on observation pairs: two more compiles, ~60 s
def test_cloning_beside_the_symmetry_loss_clones_the_first_view_and_saves_a_plain_agent(solved_set, tmp_path):
    """`clone.*` with `ppo.mirror_coef`: the demonstrations are replayed as (state, mirror image) pairs, cloning fits
    the policy at the state itself, both losses are logged, and the run saves a plain agent."""
    config = clone_config(solved_set, "clone.updates=2", "clone.coef=0.5", "clone.batch=2", "ppo.mirror_coef=1.0")
    demos, size = load_demonstrations(config)
    env, params = demonstration_env(config, size)
    plain_env, plain_params = demonstration_env(clone_config(solved_set, "clone.updates=1"), size)
    plain, _, _ = replay_observations(plain_env, plain_params, demos, jax.random.key(0), 2)
    # the first view is the state itself, bit for bit, compiled as kinetix compiles: under the suite's fast codegen
    # the pair's replay and the plain one are fused differently, and a contact rounds them apart after 24 steps
    done = subprocess.run(
        [sys.executable, "-c", FIRST_VIEW, str(solved_set)],
        env=release_env() | {"PYTHONPATH": str(REPO / "tests")},
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert done.returncode == 0 and done.stdout.split() == ["equal", "mirrored"], done.stderr[-3000:]
    plain_network, optimizer = make_network(config.model, config.env), optax.adam(3e-3)
    weights = jax.jit(plain_network.init)(jax.random.key(1), jax.tree.map(lambda x: x[0], plain))
    steps = [  # one cloning step on pairs with the run's network is the plain step on the states
        clone_step(
            weights,
            optimizer.init(weights),
            p,
            demos,
            jax.random.key(2),
            env=e,
            network=n,
            optimizer=optimizer,
            count=2,
        )
        for e, p, n in ((env, params, training_network(config)), (plain_env, plain_params, plain_network))
    ]
    jax.tree.map(lambda a, b: np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-6), steps[0][0], steps[1][0])
    np.testing.assert_allclose(steps[0][2]["clone_loss"], steps[1][2]["clone_loss"], rtol=1e-6, atol=1e-6)
    train(config, tmp_path / "both")
    steps = [json.loads(line)["clone_step"] for line in (tmp_path / "both" / "clone.jsonl").read_text().splitlines()]
    assert steps == [1, 2]
    lines = [json.loads(line) for line in (tmp_path / "both" / "metrics.jsonl").read_text().splitlines()]
    assert all(np.isfinite(line["clone_loss"]) and line["mirror_loss"] >= 0.0 for line in lines)
    assert not load_policy(tmp_path / "both").config.model.reads_pairs
