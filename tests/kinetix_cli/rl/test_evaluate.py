"""Evaluation plays a policy in its run's own environment, with each level's own engine constants."""

from __future__ import annotations

import json

import pytest

from helpers.levels import FALL
from helpers.runs import tiny_config
from kinetix_cli.errors import UserError
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.evaluate import Evaluator, evaluation_record, suite_summary


@pytest.fixture(scope="module")
def fall_levels(tmp_path_factory):
    """FALL as it is, and with the engine time step doubled in the level file."""
    folder = tmp_path_factory.mktemp("fall")
    (folder / "fall.json").write_text(json.dumps(FALL))
    (folder / "fall-fast.json").write_text(json.dumps(FALL | {"params": {"dt": 2 / 60}}))
    return [folder / "fall.json", folder / "fall-fast.json"]


def test_episodes_run_at_the_runs_frame_skip_and_the_levels_time_step(tiny_run, fall_levels):
    """The green ball needs the same simulated time to land whatever the policy does, so at the tiny run's frame
    skip 4 the episode takes about half the environment steps it takes at the level's default time step with a
    doubled dt (the level file's), and far fewer than at frame skip 2 (~0.6 s of fall at 2 x 1/60 s per step)."""
    policy = load_policy(tiny_run)
    assert policy.config.env.frame_skip == 4
    normal, fast = Evaluator(policy.config, fall_levels, attempts=2)(policy.params)
    assert normal.solve_rate == fast.solve_rate == 1.0
    assert 7 < normal.mean_length < 15 and fast.mean_length <= 0.6 * normal.mean_length


def test_a_flat_observation_policy_plays_its_own_size_only(fall_levels):
    config = tiny_config("env.observation=symbolic-flat", "model.name=flat-mlp", "env.size=m")
    with pytest.raises(UserError, match="a size-s level; this policy reads symbolic-flat observations of size m"):
        Evaluator(config, fall_levels, attempts=1)


def test_suite_summary_means_per_folder(tiny_run, fall_levels):
    policy = load_policy(tiny_run)
    results = Evaluator(policy.config, fall_levels, attempts=2)(policy.params)
    summary = suite_summary(results)
    assert summary["all"]["levels"] == 2 and summary[str(fall_levels[0].parent)]["solve_rate"] == 1.0


def test_a_policy_joined_with_its_mirror_image_plays_and_says_so(tiny_run, fall_levels):
    """`--mirror`: the episodes observe pairs (`MirrorPairEnv`) and the record names the mode; a bad mode is one
    error before anything is built."""
    policy = load_policy(tiny_run)
    normal, fast = Evaluator(policy.config, fall_levels, attempts=2, mirror="mean")(policy.params)
    assert normal.solve_rate == fast.solve_rate == 1.0
    assert evaluation_record("tiny", 1, 2, 0, [normal], mirror="mean")["mirror"] == "mean"
    with pytest.raises(UserError, match="--mirror: unknown mode 'left'; choose one of mean, geometric, value"):
        Evaluator(policy.config, fall_levels, attempts=2, mirror="left")


@pytest.mark.parametrize("model", ["pi-mlp", "transformer"])
def test_the_attention_mask_is_computed_only_for_the_model_that_reads_it(model):
    config = tiny_config(f"model.name={model}")
    [(_, _, env, *_)] = Evaluator(config, ["levels/s/pad-to-pad.json"], attempts=1)._groups
    assert env.attention is (model == "transformer")
