"""Training runs on disk: metrics and checkpoints are written, a resumed run ends where an uninterrupted one does,
bit for bit, and the run's evaluations are those of `kinetix eval`. Every run here is the tiny run of
`helpers.runs` (one compiled update for the whole session)."""

from __future__ import annotations

import dataclasses
import importlib.util
import json

import jax
import numpy as np
import pytest

from helpers.paths import EXPERIMENTS, LEVELS
from helpers.runs import EVAL_LEVEL, tiny_config
from kinetix_cli.config import load_config
from kinetix_cli.constants import EVAL_FORMAT
from kinetix_cli.env.level import level_count
from kinetix_cli.errors import UserError
from kinetix_cli.io import read_format
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.evaluate import evaluate
from kinetix_cli.rl.pool import level_pool
from kinetix_cli.rl.train import finetune_config, train


class Crash(Exception):
    pass


def metrics(run_dir) -> list[dict]:
    return [json.loads(line) for line in (run_dir / "metrics.jsonl").read_text().splitlines()]


def test_resume_after_a_crash_matches_an_uninterrupted_run(tmp_path, tiny_run, tiny_pool):
    def crash_after_3(record):
        if record["update"] == 3:
            raise Crash

    config = tiny_config()
    with pytest.raises(Crash):
        train(config, tmp_path / "cut", pool=tiny_pool, progress=crash_after_3)
    assert sorted(p.name for p in (tmp_path / "cut" / "checkpoints").iterdir()) == ["2"]
    resumed = train(config, tmp_path / "cut", resume=True, pool=tiny_pool)

    jax.tree.map(np.testing.assert_array_equal, load_policy(tiny_run).params, resumed.params)
    lines, whole = metrics(tmp_path / "cut"), metrics(tiny_run)
    assert [x["update"] for x in lines] == [1, 2, 3, 4, 5, 6]
    assert {"steps", "sps", "return", "solve_rate", "policy_loss", "value_loss", "entropy"} <= set(lines[0])
    evaluated = [(x["update"], x["eval_solve_rate"], x["eval_return"]) for x in lines if "eval_solve_rate" in x]
    assert [e[0] for e in evaluated] == [4, 6]
    assert evaluated == [(x["update"], x["eval_solve_rate"], x["eval_return"]) for x in whole if "eval_return" in x]
    drop = ("sps",)
    assert [{k: v for k, v in x.items() if k not in drop} for x in lines] == [
        {k: v for k, v in x.items() if k not in drop} for x in whole
    ]


def test_a_wall_clock_budget_ends_the_run_as_its_last_update_would(tmp_path, tiny_run, tiny_pool):
    config = tiny_config("run.minutes=1e-9")  # spent by the first update
    run_dir = tmp_path / "budget"
    train(config, run_dir, pool=tiny_pool)
    lines = metrics(run_dir)
    assert [x["update"] for x in lines] == [1] and "eval_solve_rate" in lines[0]  # evaluated as at the end
    assert sorted(p.name for p in (run_dir / "checkpoints").iterdir()) == ["1"]
    train(config, run_dir, resume=True, pool=tiny_pool)  # the budget is used up: nothing more runs
    assert [x["update"] for x in metrics(run_dir)] == [1]
    with pytest.raises(UserError, match="only run.minutes may change"):
        train(tiny_config("run.minutes=1e-9", "run.seed=1"), run_dir, resume=True, pool=tiny_pool)
    extended = train(tiny_config("run.minutes=1000"), run_dir, resume=True, pool=tiny_pool)  # a larger budget
    assert [x["update"] for x in metrics(run_dir)] == [1, 2, 3, 4, 5, 6]
    jax.tree.map(np.testing.assert_array_equal, load_policy(tiny_run).params, extended.params)  # as if never stopped


def test_evaluation_during_training_is_kinetix_eval_of_the_parameters(tiny_run):
    policy = load_policy(tiny_run)
    config = policy.config
    assert policy.update == 6 and config == tiny_config()
    (result,) = evaluate(config, policy.params, [EVAL_LEVEL], config.run.eval_attempts, seed=config.run.seed)
    last = metrics(tiny_run)[-1]
    assert last["eval_solve_rate"] == result.solve_rate and last["eval_return"] == result.mean_return
    # each evaluation's per-level record, as `kinetix eval --json` writes it
    assert sorted(f.name for f in (tiny_run / "evaluations").iterdir()) == ["4.json", "6.json"]
    record = read_format(tiny_run / "evaluations" / "6.json", EVAL_FORMAT)
    assert (record["update"], record["attempts"], record["seed"]) == (6, config.run.eval_attempts, config.run.seed)
    assert record["levels"] == [dataclasses.asdict(result)] and record["suites"]["all"]["levels"] == 1


def test_the_pool_carries_each_level_files_engine_constants(tmp_path):
    """A level file's `params` reach the training levels (they used to be dropped by pretrain and finetune)."""
    data = json.loads((LEVELS / "s/pad-to-pad.json").read_text())
    data["params"] = {"dt": 0.02, "base_thruster_power": 6.0}
    (tmp_path / "tuned.json").write_text(json.dumps(data))
    config = tiny_config(f"levels.files=[levels/s/pad-to-pad.json, {tmp_path / 'tuned.json'}]")
    pool = level_pool(config)
    assert level_count(pool) == 2
    np.testing.assert_allclose(pool.engine_params.dt, [1 / 60, 0.02], atol=1e-8)  # [s]: float32 ulp of 0.02 is 2e-9
    np.testing.assert_allclose(pool.engine_params.base_thruster_power, [10.0, 6.0], atol=1e-6)  # [N]


def test_missing_evaluation_levels_fail_before_training(tmp_path, tiny_pool):
    config = tiny_config("run.eval_levels=[levels/nowhere]")
    with pytest.raises(UserError, match="levels/nowhere: no such file"):
        train(config, tmp_path / "run", pool=tiny_pool)
    assert not (tmp_path / "run" / "metrics.jsonl").exists()


def test_refuses_to_overwrite_a_run(tmp_path, tiny_pool):
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "notes.txt").write_text("mine")
    with pytest.raises(UserError, match="not empty"):
        train(tiny_config(), tmp_path / "run", pool=tiny_pool)


def test_asking_for_wandb_without_it_is_one_clear_error(tmp_path, tiny_pool, monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "wandb" else real(name, *a))
    config = tiny_config("run.wandb=offline")
    with pytest.raises(
        UserError, match=r"run.wandb=offline: wandb is not installed; install it with pip install 'kinetix\[wandb\]'"
    ):
        train(config, tmp_path / "run", pool=tiny_pool)
    assert not (tmp_path / "run").exists()


@pytest.mark.slow
def test_wandb_offline_logs_next_to_the_run(tmp_path, tiny_pool):
    config = tiny_config()
    config = dataclasses.replace(config, run=dataclasses.replace(config.run, wandb="offline"))
    train(config, tmp_path / "run", pool=tiny_pool)
    assert list((tmp_path / "run" / "wandb").glob("offline-run-*"))


def test_init_from_loads_the_checkpoint_parameters(tmp_path, tiny_run, tiny_pool):
    wider = tiny_config("model.width=32", f"run.init_from={tiny_run}")
    with pytest.raises(UserError, match="does not match"):  # the checkpoint was read and compared
        train(wider, tmp_path / "wider", pool=tiny_pool)

    def distance(a, b):
        return max(float(np.abs(x - y).max()) for x, y in zip(jax.tree.leaves(a), jax.tree.leaves(b), strict=True))

    loaded = load_policy(tiny_run).params
    tuned = train(tiny_config(f"run.init_from={tiny_run}"), tmp_path / "a", pool=tiny_pool)
    fresh = train(tiny_config("run.seed=1"), tmp_path / "b", pool=tiny_pool)
    # six Adam updates move each weight by about 6 lr = 2e-3; another seed's initialisation is far away
    assert distance(tuned.params, loaded) < 0.01 < distance(fresh.params, loaded)


def strong_habit(params):
    """`params` with the actor's output layer x1000: the same preferences, entropy near 0."""
    heads = params["params"]["ActorCriticHeads_0"]
    confident = {**heads, "actor_head": jax.tree.map(lambda x: 1000 * x, heads["actor_head"])}
    return {"params": {**params["params"], "ActorCriticHeads_0": confident}}


def test_a_fresh_policy_head_forgets_the_loaded_habit_and_keeps_the_rest(tmp_path, tiny_run, tiny_pool):
    def without_head(params):
        heads = params["params"]["ActorCriticHeads_0"]
        return {**params["params"], "ActorCriticHeads_0": {k: v for k, v in heads.items() if k != "actor_head"}}

    loaded = load_policy(tiny_run).params
    habit = strong_habit(loaded)
    fresh_head = tiny_config(f"run.init_from={tiny_run}", "run.fresh_policy_head=true")
    fresh = train(fresh_head, tmp_path / "fresh", pool=tiny_pool, init_params=habit)

    first_entropy = metrics(tmp_path / "fresh")[0]["entropy"]
    # [nats]: a new network's ~5.78 (5%), not the habit's ~0.5
    assert first_entropy == pytest.approx(metrics(tiny_run)[0]["entropy"], abs=0.3)
    moved = jax.tree.map(lambda a, b: float(np.abs(a - b).max()), without_head(fresh.params), without_head(habit))
    assert max(jax.tree.leaves(moved)) < 0.01  # the rest kept: six Adam steps move a weight by about 2e-3
    with pytest.raises(UserError, match="run.fresh_policy_head: needs run.init_from"):
        tiny_config("run.fresh_policy_head=true")


def test_a_policy_temperature_softens_the_loaded_habit(tmp_path, tiny_run, tiny_pool):
    loaded = load_policy(tiny_run).params
    heads = loaded["params"]["ActorCriticHeads_0"]
    habit = strong_habit(loaded)
    softened = train(
        tiny_config(f"run.init_from={tiny_run}", "run.policy_temperature=1000"),
        tmp_path / "soft",
        pool=tiny_pool,
        init_params=habit,
    )
    # logits / 1000 undo the x1000: the loaded network's entropy (tiny_run's own, six updates from a new one)
    soft_entropy = metrics(tmp_path / "soft")[0]["entropy"]
    assert soft_entropy == pytest.approx(metrics(tiny_run)[0]["entropy"], abs=0.3)  # [nats]: 5% of ~5.78
    head = softened.params["params"]["ActorCriticHeads_0"]["actor_head"]
    moved = jax.tree.map(lambda a, b: float(np.abs(a - b).max()), head, heads["actor_head"])
    assert max(jax.tree.leaves(moved)) < 0.01
    with pytest.raises(UserError, match="run.policy_temperature: needs run.init_from"):
        tiny_config("run.policy_temperature=3")
    with pytest.raises(UserError, match="with run.fresh_policy_head there is none"):
        tiny_config(f"run.init_from={tiny_run}", "run.fresh_policy_head=true", "run.policy_temperature=3")
    with pytest.raises(UserError, match="env.action 'continuous' has none"):
        tiny_config(f"run.init_from={tiny_run}", "env.action=continuous", "run.policy_temperature=3")


def test_a_fresh_critic_forgets_the_loaded_values_and_keeps_the_rest(tmp_path, tiny_run, tiny_pool):
    def split(params):
        heads = params["params"]["ActorCriticHeads_0"]
        critic = {k: heads[k] for k in ("critic", "critic_head")}
        return critic, {**params["params"], "ActorCriticHeads_0": {k: v for k, v in heads.items() if k not in critic}}

    def distance(a, b):
        return max(float(np.abs(x - y).max()) for x, y in zip(jax.tree.leaves(a), jax.tree.leaves(b), strict=True))

    loaded = load_policy(tiny_run).params
    heads = loaded["params"]["ActorCriticHeads_0"]
    wild = {k: jax.tree.map(lambda x: 1000 * x, heads[k]) for k in ("critic", "critic_head")}  # values from elsewhere
    other = {"params": {**loaded["params"], "ActorCriticHeads_0": {**heads, **wild}}}
    config = tiny_config(f"run.init_from={tiny_run}", "run.fresh_critic=true")
    tuned = train(config, tmp_path / "c", pool=tiny_pool, init_params=other)
    critic, rest = split(tuned.params)
    # the critic starts from this run's own initialisation (seed 0, tiny_run's: six updates away), not the x1000
    assert distance(critic, split(loaded)[0]) < 0.02
    assert distance(rest, split(other)[1]) < 0.01  # actor and features kept
    with pytest.raises(UserError, match="run.fresh_critic: needs run.init_from"):
        tiny_config("run.fresh_critic=true")


@pytest.mark.slow  # ~28 s: two more runs compile; make test keeps the restart's memory across a resume (below)
def test_a_run_whose_first_updates_solve_nothing_starts_again_from_the_features(tmp_path, tiny_run, tiny_pool):
    loaded = load_policy(tiny_run).params
    habit = strong_habit(loaded)
    restart = [f"run.init_from={tiny_run}", "run.restart_unsolved_after=2"]

    train(tiny_config(*restart), tmp_path / "solves", pool=tiny_pool, init_params=habit)
    records = metrics(tmp_path / "solves")
    assert sum(r["solve_rate"] * r["episodes"] for r in records[:2]) > 0  # the habit solves rocket-car-jump: kept
    assert not any("restarted" in r for r in records)

    stuck = tiny_config(*restart, "levels.files=[levels/s/jet-ball-hop.json]")
    train(stuck, tmp_path / "stuck", init_params=habit)
    records = metrics(tmp_path / "stuck")
    assert sum(r["solve_rate"] * r["episodes"] for r in records[:2]) == 0  # no agent of ours solves jet-ball-hop
    assert [r.get("restarted") for r in records] == [None, 1.0, None, None, None, None]
    assert records[2]["entropy"] == pytest.approx(metrics(tiny_run)[0]["entropy"], abs=0.6)  # [nats]; a fresh head's
    with pytest.raises(UserError, match="run.restart_unsolved_after: needs run.init_from"):
        tiny_config("run.restart_unsolved_after=2")
    with pytest.raises(UserError, match="is not before the run's last"):
        tiny_config(*restart, "run.restart_unsolved_after=6")  # the tiny run has 6 updates


def test_a_resumed_run_remembers_what_its_first_updates_solved(tmp_path, tiny_run, tiny_pool):
    def crash_after_3(record):
        if record["update"] == 3:
            raise Crash

    habit = strong_habit(load_policy(tiny_run).params)
    config = tiny_config(f"run.init_from={tiny_run}", "run.restart_unsolved_after=3")
    with pytest.raises(Crash):
        train(config, tmp_path / "cut", pool=tiny_pool, init_params=habit, progress=crash_after_3)
    train(config, tmp_path / "cut", resume=True, pool=tiny_pool, init_params=habit)  # from the update-2 checkpoint
    records = metrics(tmp_path / "cut")
    solved = [r["solve_rate"] * r["episodes"] for r in records]
    # The habit solves episodes in update 2 and none in update 3: only the count rebuilt from the metrics of
    # updates 1-2 keeps the resumed run from starting again at update 3.
    assert solved[1] > 0 and solved[2] == 0
    assert not any("restarted" in r for r in records)


def test_a_saved_config_rebuilds_the_run(tiny_run):
    assert load_config(tiny_run / "config.yaml") == tiny_config()
    assert json.loads((tiny_run / "versions.json").read_text())["format"] == "kinetix-versions/1"


def test_finetune_config_keeps_the_agents_interface_unless_set():
    """Fine-tuning keeps the pre-trained model, observation, action type and frame skip (the tiny run's 4 where
    finetune.yaml says 2); a --set still wins; levels of two sizes are refused."""
    pretrained = tiny_config()
    config = finetune_config(EXPERIMENTS / "finetune.yaml", [EVAL_LEVEL], pretrained)
    assert config.model == pretrained.model and config.env.frame_skip == 4 and config.env.size == "s"
    assert config.env.dense_reward_scale == 0.2  # the fine-tuning config's own reward setting
    assert config.levels.files == config.run.eval_levels == (EVAL_LEVEL,)
    scratch = finetune_config(EXPERIMENTS / "finetune.yaml", [EVAL_LEVEL], None)
    assert scratch.model.name == "transformer" and scratch.env.frame_skip == 2
    assert config.run.init_from is None and scratch.run.init_from is None
    mine = finetune_config(EXPERIMENTS / "finetune.yaml", [EVAL_LEVEL], pretrained, ["env.frame_skip=3"], "a: b/1")
    assert mine.env.frame_skip == 3 and mine.run.init_from == "a: b/1"  # where it started, recorded as given
    with pytest.raises(UserError, match="sizes m, s"):
        finetune_config(EXPERIMENTS / "finetune.yaml", [EVAL_LEVEL, "levels/m/arm-sweep-ball.json"], pretrained)


SFL_ON_FRESH = ["curriculum.name=sfl", "curriculum.score_levels=8", "curriculum.score_batch=8"]
SFL_ON_FRESH += ["curriculum.score_steps=8", "curriculum.buffer_size=4", "curriculum.refresh_every=2"]


@pytest.mark.slow
@pytest.mark.parametrize("curriculum", [[], SFL_ON_FRESH], ids=["dr", "sfl"])
def test_fresh_levels_train_and_resume_bit_identically(tmp_path, curriculum):
    """Source 'fresh': every update samples new levels in the jit (with SFL: its candidates too, and half of each
    update's levels come from the buffer); a resumed run still ends bit-identical."""
    config = tiny_config(
        "levels.source=fresh", "levels.files=[]", "ppo.total_timesteps=192", "run.eval_every=0", *curriculum
    )

    def crash_after_2(record):
        if record["update"] == 2:
            raise Crash

    whole = train(config, tmp_path / "whole")
    with pytest.raises(Crash):
        train(config, tmp_path / "cut", progress=crash_after_2)
    resumed = train(config, tmp_path / "cut", resume=True)
    jax.tree.map(np.testing.assert_array_equal, whole.params, resumed.params)
    assert metrics(tmp_path / "cut")[-1]["return"] == metrics(tmp_path / "whole")[-1]["return"]


@pytest.mark.slow  # a second compile of the PPO update (on pairs, with the symmetry loss): ~40 s
def test_a_run_with_the_symmetry_loss_logs_it_and_is_a_plain_agent(tmp_path, tiny_run, tiny_pool):
    """`ppo.mirror_coef`: the run trains on observation pairs from a plain run's parameters, logs the loss, and
    what it saves is a plain agent that `kinetix eval` plays with one view."""
    config = tiny_config("ppo.mirror_coef=1.0", f"run.init_from={tiny_run}")
    runner = train(config, tmp_path / "loss", pool=tiny_pool)
    assert all(record["mirror_loss"] >= 0.0 for record in metrics(tmp_path / "loss"))
    loaded = load_policy(tmp_path / "loss")
    assert not loaded.config.model.reads_pairs
    assert jax.tree.structure(runner.params) == jax.tree.structure(load_policy(tiny_run).params)
    (result,) = evaluate(loaded.config, runner.params, [LEVELS / "s" / "pad-to-pad.json"], 2)
    assert 0.0 <= result.solve_rate <= 1.0 and result.mean_length > 0


@pytest.mark.slow  # a second compile of the PPO update (the model reads pairs): ~40 s
def test_a_mirror_joined_model_trains_from_a_plain_run_and_evaluates(tmp_path, tiny_run, tiny_pool):
    """`model.mirror`: a plain run's parameters start it, it trains on observation pairs, and `kinetix eval` plays it
    with its own joined policy."""
    config = tiny_config("model.mirror=geometric", f"run.init_from={tiny_run}")
    runner = train(config, tmp_path / "mirror", pool=tiny_pool)
    assert jax.tree.structure(runner.params) == jax.tree.structure(load_policy(tiny_run).params)
    (result,) = evaluate(load_policy(tmp_path / "mirror").config, runner.params, [LEVELS / "s" / "pad-to-pad.json"], 2)
    assert 0.0 <= result.solve_rate <= 1.0 and result.mean_length > 0
