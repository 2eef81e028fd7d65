"""kill -9 of `kinetix generate` and `kinetix pretrain` at several points (before the first shard or checkpoint,
while a file is being written, after one), then the same command again (with --resume for pretrain): the result
equals an uninterrupted run. Real processes, so marked slow (`make test-all`)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import jax
import numpy as np
import pytest

from helpers.processes import process_env
from helpers.runs import TINY, set_args
from kinetix_cli.rl.agents import load_policy

pytestmark = pytest.mark.slow

KINETIX = [sys.executable, "-c", "from kinetix_cli.cli.app import main; main()"]


@pytest.fixture(scope="module")
def env():
    """The suite's compile cache, so every process after the first skips most of its compile."""
    return process_env()


def run(args: list, env: dict) -> None:
    done = subprocess.run([*KINETIX, *map(str, args)], env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-2000:]


def kill_when(args: list, env: dict, ready: Callable[[], bool], what: str) -> None:
    """Start `kinetix ARGS`, kill -9 it as soon as `ready()` holds."""
    process = subprocess.Popen([*KINETIX, *map(str, args)], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 900
    while not ready():
        if process.poll() is not None or time.monotonic() > deadline:
            process.kill()
            pytest.fail(f"the process ended before it was {what}: {process.stderr.read().decode()[-1000:]}")
        time.sleep(0.002)
    os.kill(process.pid, signal.SIGKILL)
    process.wait()


def files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


GENERATE = ["generate", "--size", "s", "--count", "600", "--seed", "4", "--chunk", "64", "--shard-size", "100"]


@pytest.fixture(scope="module")
def uninterrupted_set(tmp_path_factory, env):
    out = tmp_path_factory.mktemp("generate") / "whole"
    run([*GENERATE, "--out", out], env)
    return out


def shards(out: Path) -> int:
    return len(list(out.glob("shard-*.npz"))) if out.exists() else 0


GENERATE_POINTS = {
    "before the first shard": lambda out: (out / "progress.json").exists(),
    "while a shard is written": lambda out: any(out.glob(".shard-*.tmp")) if out.exists() else False,
    "after two shards": lambda out: shards(out) >= 2,
}


@pytest.mark.parametrize("point", list(GENERATE_POINTS))
def test_generate_killed_then_rerun_equals_an_uninterrupted_set(tmp_path, env, uninterrupted_set, point):
    out = tmp_path / "cut"
    kill_when([*GENERATE, "--out", out], env, lambda: GENERATE_POINTS[point](out), point)
    assert (out / "manifest.json").exists() is False
    run([*GENERATE, "--out", out], env)
    assert files(out) == files(uninterrupted_set)


PRETRAIN = ["pretrain", "--config", "experiments/cpu-small.yaml", *set_args(TINY)]
LONGER = ["--set", "ppo.total_timesteps=1920", "--set", "run.checkpoint_every=3"]  # 30 updates, checkpoint every 3


@pytest.fixture(scope="module")
def uninterrupted_run(tmp_path_factory, env):
    out = tmp_path_factory.mktemp("pretrain") / "whole"
    run([*PRETRAIN, *LONGER, "--run-dir", out], env)
    return out


def metric_lines(run_dir: Path) -> list[dict]:
    return [{k: v for k, v in json.loads(x).items() if k != "sps"} for x in (run_dir / "metrics.jsonl").open()]


def checkpoints(run_dir: Path) -> list[str]:
    folder = run_dir / "checkpoints"
    return [p.name for p in folder.iterdir() if p.name.isdigit()] if folder.exists() else []


PRETRAIN_POINTS = {
    "before the first checkpoint": lambda d: (d / "metrics.jsonl").exists() and (d / "metrics.jsonl").stat().st_size,
    "while a checkpoint is written": lambda d: any((d / "checkpoints").glob("*tmp*")) if d.exists() else False,
    "after two checkpoints": lambda d: len(checkpoints(d)) >= 2,
}


@pytest.mark.parametrize("point", list(PRETRAIN_POINTS))
def test_pretrain_killed_then_resumed_equals_an_uninterrupted_run(tmp_path, env, uninterrupted_run, point):
    out = tmp_path / "cut"
    kill_when([*PRETRAIN, *LONGER, "--run-dir", out], env, lambda: PRETRAIN_POINTS[point](out), point)
    run([*PRETRAIN, *LONGER, "--run-dir", out, "--resume"], env)
    assert metric_lines(out) == metric_lines(uninterrupted_run)
    assert not list(out.rglob("*tmp*")), "the resumed run left the killed run's temporaries"
    jax.tree.map(np.testing.assert_array_equal, load_policy(out).params, load_policy(uninterrupted_run).params)
