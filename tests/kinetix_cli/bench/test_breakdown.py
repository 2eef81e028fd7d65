"""`kinetix bench train --breakdown` and `--trace`: where an update's time goes, its FLOPs and the matmul limit;
bad options are one-line errors before anything compiles."""

from __future__ import annotations

import inspect
import json
import types

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from engine import SIZES
from helpers.cli import kinetix
from helpers.paths import EXPERIMENTS
from kinetix_cli.bench.breakdown import (
    PHASES,
    UpdateSetup,
    matmul_shapes,
    scoring_phase,
    scoring_time,
    xla_flops,
)
from kinetix_cli.bench.env import random_levels
from kinetix_cli.bench.train import TrainBenchConfig, bench_train, experiment_for, scoring_settings
from kinetix_cli.cli.bench import SCORING, bench_train_command
from kinetix_cli.config import load_config
from kinetix_cli.env.factory import make_env
from kinetix_cli.errors import UserError
from kinetix_cli.rl.buffer import empty_buffer
from kinetix_cli.rl.networks import make_network
from kinetix_cli.rl.ppo import init_runner

TINY = {"envs": (4,), "num_steps": 4, "epochs": 1, "minibatches": 2, "width": 8, "layers": 1, "min_time": 0.0}


@pytest.mark.parametrize(
    ("where", "message"),
    [
        ("file", "--trace {tmp}/file: is a file, not a folder"),
        ("file/inside", "--trace {tmp}/file/inside: cannot be created: {tmp}/file is not a folder"),
    ],
)
def test_bad_trace_folder_exits_2_with_one_line(capsys, tmp_path, where, message):
    (tmp_path / "file").write_text("not a folder")
    out = kinetix(capsys, "bench", "train", "--breakdown", "--trace", str(tmp_path / where))
    code = out.code
    assert code == 2
    assert message.format(tmp=tmp_path) in out.err
    assert "Traceback" not in out.err and len(out.err.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("change", "flag"),
    [({"size": "xl"}, "--size"), ({"models": ("cnn",)}, "--models"), ({"minibatches": 3}, "--minibatches")],
)
def test_breakdown_rejects_impossible_sizes(change, flag):
    with pytest.raises(UserError, match=flag):
        bench_train(TrainBenchConfig(**(TINY | change), breakdown=True))


def test_breakdown_refuses_several_devices_and_asks_for_one_by_default(monkeypatch):
    asked = []
    monkeypatch.setattr(
        "kinetix_cli.bench.train.make_mesh", lambda count: asked.append(count) or types.SimpleNamespace(size=2)
    )
    with pytest.raises(UserError, match="--breakdown: measures on one device, not 2; add --devices 1"):
        bench_train(TrainBenchConfig(**TINY, breakdown=True, devices=(2,)))
    with pytest.raises(UserError):  # (the stand-in mesh has 2 devices whatever it is asked)
        bench_train(TrainBenchConfig(**TINY, breakdown=True))  # the CPU split into one device per core
    assert asked == [2, 1]


def test_xla_flops_of_a_matmul_is_its_multiply_adds():
    a, b = jnp.ones((16, 32)), jnp.ones((32, 8))
    assert xla_flops(jax.jit(jnp.matmul).lower(a, b).compile()) == 2 * 16 * 32 * 8


@pytest.mark.parametrize(
    ("cost", "flops"), [({"flops": 6.0}, 6.0), ([{"flops": 2.0}, {"flops": 4.0}], 6.0), ([{}], 0.0), (None, 0.0)]
)
def test_xla_flops_reads_a_dict_or_a_list_of_dicts(cost, flops):
    assert xla_flops(types.SimpleNamespace(cost_analysis=lambda: cost)) == flops


def test_matmul_shapes_follow_the_first_layer_and_the_hidden_layers():
    config = TrainBenchConfig(**(TINY | {"envs": (16,), "width": 32}))  # minibatch: 16 x 4 / 2 = 32 rows
    flat = _setup(experiment_for(config, "flat-mlp", 16))
    assert matmul_shapes(flat, {"obs": np.zeros((16, 30), np.float32)}) == [(32, 30, 32), (32, 32, 32)]
    entities = {
        "polygons": np.zeros((16, 5, 27), np.float32),  # the widest entity features: 5 per row
        "circles": np.zeros((16, 3, 20), np.float32),
        "gravity": np.zeros((16, 2), np.float32),
        "mask": np.zeros((16, 5, 64), bool),
    }
    assert matmul_shapes(_setup(experiment_for(config, "rel-mlp", 16)), entities) == [(160, 27, 32), (32, 32, 32)]


def _setup(experiment) -> UpdateSetup:
    return UpdateSetup(experiment, env=None, env_params=None, network=None, pool=None)


def test_scoring_is_one_refresh_of_the_buffer_and_what_a_run_pays_for_it_per_update():
    config = TrainBenchConfig(**TINY, score_levels=4, score_attempts=2, score_steps=3, refresh_every=4)
    experiment = experiment_for(config, "flat-mlp", 4)
    env, env_params = make_env(experiment.env)
    network = make_network(experiment.model, experiment.env)
    pool = random_levels(SIZES["s"], 4, 0)
    runner = init_runner(env, network, experiment.ppo, pool, jax.random.key(0))
    curriculum, setup = scoring_settings(config), UpdateSetup(experiment, env, env_params, network, pool)
    scored = scoring_time(setup, runner, curriculum, 6.0, 0.0)
    assert (scored.levels, scored.attempts, scored.steps, scored.refresh_every) == (4, 2, 3, 4)
    assert scored.refresh_ms == pytest.approx(1e3 * 4 * 2 * 3 / scored.steps_per_s, rel=1e-9, abs=1e-9)  # [ms]
    assert scored.per_update_ms == pytest.approx(scored.refresh_ms / 4, rel=1e-9, abs=1e-9)  # [ms]
    share = scored.per_update_ms / (6.0 + scored.per_update_ms)
    assert scored.share == pytest.approx(share, rel=1e-9, abs=1e-12)  # [fraction]
    assert scoring_settings(TrainBenchConfig(**TINY)) is None  # 0 levels (the library's default): no scoring
    empty = empty_buffer(pool, curriculum.buffer_size)
    *_, refreshed = jax.jit(scoring_phase(setup, curriculum))(runner.params, runner.key, empty)
    assert int(refreshed.rounds) == 1 and int(refreshed.size) == curriculum.buffer_size == 4  # a whole refresh


def test_the_breakdown_scores_as_the_general_recipe_by_default():
    recipe = load_config(EXPERIMENTS / "general.yaml").curriculum
    assert {name: getattr(recipe, name) for name in SCORING} == SCORING
    defaults = {name: p.default.default for name, p in inspect.signature(bench_train_command).parameters.items()}
    assert {name: defaults[name] for name in SCORING} == SCORING


# ~90 s on a loaded 2-core VM (compiles the update, the rollout, each phase and the env alone): make test-all
@pytest.mark.slow
def test_breakdown_and_trace_of_rel_mlp_through_the_cli(capsys, tmp_path):
    out, trace = tmp_path / "train.json", tmp_path / "trace"
    args = ["bench", "train", "--breakdown", "--trace", str(trace), "--models", "rel-mlp", "--envs", "4"]
    args += ["--steps", "4", "--epochs", "1", "--minibatches", "2", "--width", "8", "--layers", "1"]
    args += ["--score-levels", "4", "--score-attempts", "1", "--score-steps", "4", "--refresh-every", "2"]
    printed = kinetix(capsys, *args, "--min-time", "0", "--json", str(out))
    code = printed.code
    assert code == 0, printed.err
    assert "rel-mlp, size s, 4 envs (symbolic-entity): one update" in printed.out
    (row,) = json.loads(out.read_text())["results"]
    assert row["model"] == "rel-mlp" and row["steps_per_s"] > 0  # the fields without --breakdown stay
    b = row["breakdown"]
    assert [p["name"] for p in b["phases"]] == list(PHASES)
    assert all(p["ms"] > 0 and p["share"] > 0 for p in b["phases"])
    assert b["final_value_rows"] == 1  # 1/16 of the envs, at least one row (`ppo.truncated_rows`)
    assert b["phase_sum_ms"] == pytest.approx(sum(p["ms"] for p in b["phases"]), rel=1e-6, abs=1e-9)  # [ms]
    assert b["update_gflop"] >= b["learn_gflop"] > 0 and b["update_gflop_per_s"] > 0 and b["xla_update_gflop"] > 0
    assert b["env_only_steps_per_s"] > 0 and b["env_only_ms"] > 0
    assert {(tuple(m["shape"]), m["dtype"]) for m in b["matmuls"]} >= {((4 * 4 // 2, 8, 8), "float32")}
    assert {m["dtype"] for m in b["matmuls"]} == {"float32", "bfloat16"} and len(b["matmuls"]) == 4
    assert b["f32_limit_gflop_per_s"] > 0 and b["best_limit_gflop_per_s"] >= b["f32_limit_gflop_per_s"]
    share = b["update_gflop_per_s"] / b["f32_limit_gflop_per_s"]
    assert b["f32_limit_share"] == pytest.approx(share, rel=1e-6, abs=1e-12)  # [fraction]
    scored = b["scoring"]
    assert (scored["levels"], scored["attempts"], scored["steps"], scored["refresh_every"]) == (4, 1, 4, 2)
    assert scored["refresh_ms"] > 0
    assert scored["per_update_ms"] == pytest.approx(scored["refresh_ms"] / 2, rel=1e-9, abs=1e-9)  # [ms]
    assert "SFL per update (/2)" in printed.out
    assert row["trace"] == str(trace / "rel-mlp-s-envs4-devices1")
    assert list((trace / "rel-mlp-s-envs4-devices1").rglob("*.xplane.pb"))
