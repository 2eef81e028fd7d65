"""Agent folders: a run's policy exported with its config, checksums and evaluation; read back bit for bit by
folder or, for a shipped agent, by name in eval, rollout and finetune; damaged or mismatched files refused."""

from __future__ import annotations

import json
import shutil

import jax
import numpy as np
import pytest
from flax import traverse_util
from typer.testing import CliRunner

from helpers.cli import kinetix
from helpers.pages import read_report
from helpers.runs import EVAL_LEVEL, TINY, TRAIN_LEVELS, set_args
from kinetix_cli.cli.app import app
from kinetix_cli.config import load_config
from kinetix_cli.constants import EVAL_FORMAT, VALIDATION_FORMAT
from kinetix_cli.errors import UserError
from kinetix_cli.io import atomic_write_json
from kinetix_cli.rl import agents
from kinetix_cli.rl.checkpoints import read_policy
from kinetix_cli.rl.networks import POLICY_HEAD


@pytest.fixture(scope="module")
def exported(tmp_path_factory, tiny_run):
    """The tiny run evaluated and exported as agent `tiny-agent` (version 3): its folder."""
    work = tmp_path_factory.mktemp("agents")
    evaluation = work / "eval.json"
    result = CliRunner().invoke(
        app, ["eval", str(tiny_run), "--levels", EVAL_LEVEL, "--attempts", "2", "--json", str(evaluation)]
    )
    assert result.exit_code == 0, result.output
    folder = work / "tiny-agent"
    commands = ["kinetix pretrain --config experiments/cpu-small.yaml ...", "kinetix eval ..."]
    agents.export_agent(tiny_run, folder, name="tiny-agent", version=3, commands=commands, evaluation=evaluation)
    return folder


@pytest.fixture
def shipped(monkeypatch, exported):
    """`exported` installed as the only shipped agent."""
    monkeypatch.setattr(agents, "SHIPPED", exported.parent)
    return exported


def test_an_exported_agent_is_the_runs_policy_with_its_card(exported, tiny_run):
    assert sorted(p.name for p in exported.iterdir()) == ["agent.json", "config.yaml", "params.msgpack"]
    policy = agents.load_policy(exported)
    run_config, run_params, checkpoint = read_policy(tiny_run)
    assert policy.config == run_config and policy.update == int(checkpoint.name) == 6
    jax.tree.map(np.testing.assert_array_equal, policy.params, run_params)
    card = agents.read_card(exported)
    assert (card.name, card.version, card.trained["steps"]) == ("tiny-agent", 3, 6 * 64)
    assert card.trained["commands"][0].startswith("kinetix pretrain") and "jax" in json.dumps(card.trained)
    assert card.evaluation["attempts"] == 2 and card.evaluation["suites"]["levels/s"]["levels"] == 1
    assert (exported / "params.msgpack").stat().st_size < 100_000


def test_a_shipped_agent_is_used_by_name(capsys, shipped, tmp_path):
    listed = kinetix(capsys, "agents")
    assert listed.code == 0 and "tiny-agent" in listed.out and "384 env steps" in listed.out
    cards = json.loads(kinetix(capsys, "agents", "--json").out)
    assert [c["name"] for c in cards] == ["tiny-agent"] and cards[0]["model"].startswith("pi-mlp width 16")
    evaluated = kinetix(capsys, "eval", "tiny-agent", "--levels", EVAL_LEVEL, "--attempts", "1")
    assert evaluated.code == 0 and "rocket-car-jump" in evaluated.out
    played = kinetix(capsys, "rollout", EVAL_LEVEL, "--policy", "tiny-agent")
    assert played.code == 0 and "policy tiny-agent" in played.out
    tuned = tmp_path / "tuned"
    sets = [value for value in TINY if not value.startswith(("env.frame_skip", "run.eval_levels"))]
    args = ["finetune", *TRAIN_LEVELS, "--from", "tiny-agent", "--run-dir", tuned, "--config"]
    assert kinetix(capsys, *args, "experiments/cpu-small.yaml", *set_args(sets)).code == 0
    assert load_config(tuned / "config.yaml").env.frame_skip == 4  # the agent's own, as with --from RUN
    assert kinetix(capsys, "report", tuned, "-o", tmp_path / "report", "--no-gifs").code == 0  # a fine-tuned run
    _, payload = read_report(tmp_path / "report")  # (GIFs: viz/test_report.py)
    assert payload["runs"][0]["init_from"] == "tiny-agent" and [e["level"] for e in payload["levels"]] == TRAIN_LEVELS


def test_unknown_names_and_damaged_agents_are_one_line(capsys, shipped, tmp_path):
    line = kinetix(capsys, "eval", "general-x").error_line
    assert "general-x: no such run, checkpoint or agent folder, nor a shipped agent (shipped: tiny-agent)" in line
    line = kinetix(capsys, "rollout", EVAL_LEVEL, "--policy", "general-x").error_line
    assert "is not one of noop, random, solution, tiny-agent nor a run or agent folder" in line

    damaged = tmp_path / "damaged"
    shutil.copytree(shipped, damaged)
    data = bytearray((damaged / "params.msgpack").read_bytes())
    data[-3] ^= 0x01
    (damaged / "params.msgpack").write_bytes(bytes(data))
    line = kinetix(capsys, "eval", damaged, "--levels", EVAL_LEVEL).error_line
    assert "params.msgpack: does not match its checksum" in line

    card = json.loads((shipped / "agent.json").read_text())
    (damaged / "agent.json").write_text(json.dumps(card | {"version": "two"}))
    assert "agent.json: version: expected int, got 'two'" in kinetix(capsys, "eval", damaged).error_line
    (damaged / "agent.json").write_text(json.dumps(card | {"trained": {"update": "six"}}))
    assert (
        "agent.json: trained.update: expected an update count, got 'six'" in kinetix(capsys, "eval", damaged).error_line
    )
    (damaged / "agent.json").write_text(json.dumps(card | {"files": {**card["files"], "../x": "0"}}))
    assert (
        "agent.json: files: expected the sha256 of config.yaml and params.msgpack"
        in kinetix(capsys, "eval", damaged).error_line
    )
    (damaged / "agent.json").write_text(json.dumps(card | {"format": "kinetix-agent/9"}))
    assert "format: expected 'kinetix-agent/1', got 'kinetix-agent/9'" in kinetix(capsys, "eval", damaged).error_line


def test_older_versions_of_a_shipped_agent_load_by_name_and_version(capsys, exported, tmp_path, monkeypatch):
    """`name` is the newest version (folder `name`), `name@version` any version kept (folder `name@version`)."""
    installed = tmp_path / "shipped"
    newest, older = installed / "tiny-agent", installed / "tiny-agent@2"
    shutil.copytree(exported, newest)
    shutil.copytree(exported, older)
    card = json.loads((older / "agent.json").read_text())
    (older / "agent.json").write_text(json.dumps(card | {"version": 2}))
    monkeypatch.setattr(agents, "SHIPPED", installed)
    assert agents.shipped_names() == ["tiny-agent"]
    assert agents.resolve("tiny-agent") == agents.resolve("tiny-agent@3") == newest
    assert agents.resolve("tiny-agent@2") == older
    listed = kinetix(capsys, "agents")
    assert listed.out.index("tiny-agent v3") < listed.out.index("tiny-agent v2")
    line = kinetix(capsys, "eval", "tiny-agent@1").error_line
    assert "tiny-agent@1: no such run, checkpoint or agent folder, nor a shipped agent" in line
    assert "(shipped: tiny-agent, tiny-agent@2)" in line
    assert kinetix(capsys, "eval", "tiny-agent@2", "--levels", EVAL_LEVEL, "--attempts", "1").code == 0


def test_export_replaces_an_agent_but_nothing_else(tmp_path, tiny_run):
    folder = tmp_path / "a"
    agents.export_agent(tiny_run, folder, name="a", version=1, commands=[])
    agents.export_agent(tiny_run, folder, name="a", version=2, commands=[])
    assert agents.read_card(folder).version == 2 and sorted(p.name for p in tmp_path.iterdir()) == ["a"]
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "notes.txt").write_text("mine")
    with pytest.raises(UserError, match="not empty and not an agent folder"):
        agents.export_agent(tiny_run, tmp_path / "other", name="a", version=1, commands=[])
    with pytest.raises(UserError, match="--name 'General S'"):
        agents.export_agent(tiny_run, tmp_path / "b", name="General S", version=1, commands=[])
    wrong = tmp_path / "eval.json"
    record = {"format": "kinetix-eval/1", "policy": "elsewhere", "attempts": 2, "levels": [], "suites": {}}
    wrong.write_text(json.dumps(record))
    with pytest.raises(UserError, match="policy: evaluates 'elsewhere'"):
        agents.export_agent(tiny_run, tmp_path / "c", name="c", version=1, commands=[], evaluation=wrong)


def test_an_agent_exported_at_a_temperature_divides_only_its_action_logits(capsys, exported, tmp_path):
    hot = tmp_path / "hot"
    made = kinetix(capsys, "agents", "export", exported, "-o", hot, "--name", "hot", "--temperature", "2")
    assert made.code == 0 and agents.read_card(hot).trained["temperature"] == 2.0
    flat = lambda folder: traverse_util.flatten_dict(agents.load_policy(folder).params)  # noqa: E731
    before, after = flat(exported), flat(hot)
    for path, value in before.items():
        want = value / 2 if POLICY_HEAD in path else value
        np.testing.assert_array_equal(after[path], np.asarray(want, np.float32), err_msg=str(path))
    refused = kinetix(capsys, "agents", "export", exported, "-o", tmp_path / "x", "--name", "x", "--temperature", "0")
    assert refused.code == 2 and "--temperature 0" in refused.error_line and not (tmp_path / "x").exists()


def test_a_run_named_by_a_relative_path_loads(tiny_run, monkeypatch):
    # orbax reads checkpoint metadata only through absolute paths; users type relative ones (runs/NAME)
    params = agents.load_policy(tiny_run).params
    monkeypatch.chdir(tiny_run.parent)
    again = agents.load_policy(tiny_run.name).params
    assert all(np.array_equal(a, b) for a, b in zip(jax.tree.leaves(params), jax.tree.leaves(again), strict=True))


def assert_weighted_average(x, y, z):
    """`z` is 0.75 `x` + 0.25 `y` in float32: within 2 float32 eps of the operands' weighted sizes. Rounding the
    exact average once (or each term, then their sum) errs by at most about 1 eps of that; a relative tolerance on
    `z` fails where the two terms nearly cancel and `z` is near 0 (issue 46: 7e-12 off at -2.8e-6, on one CPU)."""
    x, y, z = (np.asarray(v, np.float64) for v in (x, y, z))
    exact = 0.75 * x + 0.25 * y
    bound = 2 * np.finfo(np.float32).eps * (0.75 * np.abs(x) + 0.25 * np.abs(y))
    error = np.abs(z - exact)
    worst = np.unravel_index(np.argmax(error - bound), error.shape) if error.ndim else ()
    assert np.all(error <= bound), f"at {worst}: {z[worst]} vs {exact[worst]}, off {error[worst]} > {bound[worst]}"


def test_a_blend_is_the_weighted_average_and_ships_like_a_run(capsys, tiny_run, exported, tmp_path):
    """`agents blend`: parameters averaged with the given weights; the card lists the sources; the blend plays
    and is shipped by `agents export` with its evaluation, keeping its sources and steps."""
    early = tiny_run / "checkpoints" / "2"
    blend = tmp_path / "blend"
    args = ["agents", "blend", early, exported, "-o", blend, "--name", "mix", "--weight", "3", "--weight", "1"]
    made = kinetix(capsys, *args)
    assert made.code == 0 and "the average of" in made.out and "x0.75" in made.out
    a, b = agents.load_policy(early).params, agents.load_policy(exported).params
    blended = agents.load_policy(blend)
    jax.tree.map(assert_weighted_average, a, b, blended.params)
    assert not np.allclose(jax.tree.leaves(a)[0], jax.tree.leaves(blended.params)[0])  # the two really differ
    card = agents.read_card(blend)
    sources = [(s["source"], s["weight"], s["update"], s["steps"]) for s in card.trained["blend"]]
    assert sources == [(str(early), 0.75, 2, 2 * 64), (str(exported), 0.25, 6, 6 * 64)]
    assert card.trained["steps"] == 8 * 64 and blended.config == load_config(exported / "config.yaml")

    evaluation = tmp_path / "eval.json"
    assert kinetix(capsys, "eval", blend, "--levels", EVAL_LEVEL, "--attempts", "2", "--json", evaluation).code == 0
    shipped = tmp_path / "shipped"
    assert kinetix(capsys, "agents", "export", blend, "-o", shipped, "--name", "mix", "--eval", evaluation).code == 0
    card = agents.read_card(shipped)
    assert card.trained["blend"][1]["source"] == str(exported) and card.trained["steps"] == 8 * 64
    assert card.evaluation["attempts"] == 2
    jax.tree.map(np.testing.assert_array_equal, agents.load_policy(shipped).params, blended.params)


def test_a_bad_blend_is_one_line(capsys, tiny_run, tmp_path):
    out = ["-o", tmp_path / "b", "--name", "b"]
    one = kinetix(capsys, "agents", "blend", tiny_run, *out)
    assert one.code == 2 and "blend: give at least two policies to average, got 1" in one.error_line
    counted = kinetix(capsys, "agents", "blend", tiny_run, tiny_run, *out, "--weight", "1")
    assert counted.code == 2 and "--weight: 1 weights for 2 policies" in counted.error_line
    negative = kinetix(capsys, "agents", "blend", tiny_run, tiny_run, *out, "--weight", "1", "--weight", "-1")
    assert negative.code == 2 and "every weight must be a positive number" in negative.error_line
    other = kinetix(capsys, "agents", "blend", tiny_run, "general-s", *out)
    assert other.code == 2 and "general-s: not the network of" in other.error_line and "model.name" in other.error_line
    assert not (tmp_path / "b").exists()


def test_a_blend_names_a_shipped_source_with_its_version(capsys, tmp_path):
    """A bare shipped name moves on with new versions, so the card records `name@version`; a policy blended
    with itself is itself."""
    version = agents.read_card(agents.SHIPPED / "general-s").version
    blend = tmp_path / "self"
    assert kinetix(capsys, "agents", "blend", "general-s", f"general-s@{version}", "-o", blend, "--name", "s").code == 0
    card = agents.read_card(blend)
    assert [s["source"] for s in card.trained["blend"]] == [f"general-s@{version}"] * 2
    assert [s["weight"] for s in card.trained["blend"]] == [0.5, 0.5]
    shipped = agents.load_policy("general-s")
    assert card.trained["steps"] == 2 * agents.read_card(agents.SHIPPED / "general-s").trained["steps"]
    jax.tree.map(np.testing.assert_array_equal, agents.load_policy(blend).params, shipped.params)


def _test_record(seed: int, rate: float) -> dict:
    """A `kinetix eval --json` record on the test suite (the paper's 74 levels), every suite at `rate`."""
    counts = {"s": 10, "m": 24, "l": 40}
    suites = {f".cache/reference-levels/{size}": {"levels": n, "solve_rate": rate} for size, n in counts.items()}
    suites["all"] = {"levels": 74, "solve_rate": rate}
    return {"policy": "tiny-agent", "seed": seed, "attempts": 50, "levels": [], "suites": suites}


def test_an_agents_card_records_what_chose_it_and_its_test_scores(capsys, exported, tmp_path):
    folder = shutil.copytree(exported, tmp_path / "agent")
    before = {name: (folder / name).read_bytes() for name in ("config.yaml", "params.msgpack")}
    validation = {
        "agent": "tiny-agent",
        "update": 6,
        "attempts": 50,
        "seed": 1000,
        "suites": {"all": {"levels": 180}},
        "score": {"heldout": 0.25, "ours": 0.125, "zero_shot": 0.2, "finetune": 0.5},
        "finetune": {"levels": {"levels/m/two-link-reach.json": {"seeds": [0, 1, 2], "solve_rate": [1.0, 0.0, 0.5]}}},
    }
    files = [tmp_path / "validation.json"] + [tmp_path / f"test-{seed}.json" for seed in (1000, 1001)]
    atomic_write_json(files[0], validation, VALIDATION_FORMAT)
    for file, seed in zip(files[1:], (1000, 1001), strict=True):
        atomic_write_json(file, _test_record(seed, 0.3), EVAL_FORMAT)
    tests = [arg for file in files[1:] for arg in ("--test", file)]
    made = kinetix(capsys, "agents", "record", folder, "--validation", files[0], *tests, "--rule", "PLAN.md, rule 1")
    assert made.code == 0 and "held out 25.0%" in made.out and "30.0% (seed 1000)" in made.out
    card = agents.read_card(folder)
    assert card.validation["score"]["finetune"] == 0.5 and set(card.test["by_seed"]) == {"1000", "1001"}
    assert card.rule == "PLAN.md, rule 1" and card.trained == agents.read_card(exported).trained
    assert {name: (folder / name).read_bytes() for name in before} == before
    agents.load_policy(folder)  # its files still match the card's checksums

    other = _test_record(1002, 0.3) | {"suites": {"levels/s": {"levels": 10, "solve_rate": 0.3}}}
    atomic_write_json(tmp_path / "other.json", other, EVAL_FORMAT)
    refused = kinetix(
        capsys, "agents", "record", folder, "--validation", files[0], "--test", tmp_path / "other.json", "--rule", "x"
    )
    assert refused.code == 2 and "not an evaluation on the test suite" in refused.error_line
    blank = kinetix(capsys, "agents", "record", folder, "--validation", files[0], *tests, "--rule", " ")
    assert blank.code == 2 and "--rule" in blank.error_line
