"""The two examples for other people's training code run, at tiny sizes: PPO on the gymnax environment, random play
on the Gymnasium vector environment."""

from __future__ import annotations

import importlib.util
import sys

import pytest

from helpers.paths import REPO


def _example(name: str):
    spec = importlib.util.spec_from_file_location(name, REPO / "examples" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # flax modules (dataclasses) look their module up
    spec.loader.exec_module(module)
    return module


def test_gymnax_ppo_trains(capsys):
    main = _example("gymnax_ppo").main
    main(["--levels", "s", "--num-envs", "8", "--num-steps", "16", "--updates", "2", "--epochs", "1"])
    out = capsys.readouterr().out
    assert "update 2/2" in out and "256 env steps" in out


def test_gymnasium_random_plays(capsys):
    result = _example("gymnasium_random").main(
        ["--levels", "s", "--num-envs", "4", "--steps", "20", "--max-steps", "8"]
    )
    assert result["episodes"] >= 1 and result["solved"] + result["failed"] <= result["episodes"]
    assert "episodes:" in capsys.readouterr().out


def test_gymnax_ppo_refuses_a_minibatch_split_that_does_not_divide():
    with pytest.raises(SystemExit):
        _example("gymnax_ppo").main(["--num-envs", "3", "--num-steps", "5", "--minibatches", "4"])
