"""Training across devices and processes gives the run of one device, with level files (every other source and
curriculum: tests/hostile/test_sources_on_devices.py). make test: a killed peer stops the other with one line, and
bad flags are one line. make test-all: the tiny run's first 4 updates (checkpoints 2 and 4, no evaluation) on 2
forced host devices in one process against the session's tiny run (1 device, this process) at its checkpoint 4, and
as 2 processes of one device each on localhost (gloo collectives), bit for bit against 2 devices; a killed process
0, with the coordination service; the tiny SFL run's first 6 updates on 2 devices against its first 6 on 1; kill -9
of either process, then --resume. Each `kinetix` process compiles its own programs: ~20 s of CPU each.

The 2-device program splits every batch and averages the gradient with an all-reduce, so its sums run in
another order than the 1-device program's: parameters agree to float32 rounding (`PARAMS_ATOL`), not bit for
bit. 2 devices in one process and 2 processes run the same partitioned program: bit for bit equal."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import jax
import numpy as np
import pytest

from helpers.processes import FORCE_2, TIMEOUT, finish, process_env, processes, run_ok, start
from helpers.runs import SFL, TINY, set_args, sfl_config
from kinetix_cli.parallel import PEER_LOST_EXIT
from kinetix_cli.rl.agents import load_policy

pytestmark = pytest.mark.xdist_group("train-parallel")  # one worker makes the module's runs

PRETRAIN = ["pretrain", "--config", "experiments/cpu-small.yaml", *set_args(TINY)]
FOUR = [*PRETRAIN, "--set", "ppo.total_timesteps=256", "--set", "run.eval_every=0"]
"""The tiny run's first 4 updates (training keys do not depend on evaluation or the total)."""
PARAMS_ATOL = 1e-5
"""Parameters of 1 device vs 2: the split batch sums the loss in another order, which changes the gradient's last
bits; Adam divides by the gradient's running scale, so a parameter whose gradient is near 0 can move by a visible
fraction of a step (lr 3e-4) more or less. Measured after 6 updates: up to 6e-8 (DR), 1.6e-6 (SFL)."""


@pytest.fixture(scope="module")
def env():
    return process_env()


@pytest.fixture(scope="module")
def two_device_run(tmp_path_factory, env):
    run_dir = tmp_path_factory.mktemp("parallel") / "two-devices"
    run_ok([start([*FOUR, "--run-dir", run_dir], env, XLA_FLAGS=FORCE_2)])
    return run_dir


@pytest.fixture(scope="module")
def two_process_run(tmp_path_factory, env):
    run_dir = tmp_path_factory.mktemp("parallel") / "two-processes"
    run_ok(processes([*FOUR, "--run-dir", run_dir], env))
    return run_dir


def params(path: Path) -> list[np.ndarray]:
    """The parameters of a run's latest checkpoint, or of one checkpoint folder."""
    return jax.tree.leaves(load_policy(path).params)


def metrics(run_dir: Path, updates: int | None = None) -> list[dict]:
    """The first `updates` lines of the run's metrics, without its speed and evaluations."""
    lines = (run_dir / "metrics.jsonl").read_text().splitlines()[:updates]
    return [{k: v for k, v in json.loads(line).items() if k != "sps" and not k.startswith("eval_")} for line in lines]


def assert_close(one: list[dict], other: list[dict]) -> None:
    assert [r.keys() for r in one] == [r.keys() for r in other]
    for a, b in zip(one, other, strict=True):
        np.testing.assert_allclose([a[k] for k in a], [b[k] for k in a], rtol=1e-4, atol=1e-6)


@pytest.mark.slow  # make test-all: also tests/hostile/test_sources_on_devices.py
def test_two_devices_train_as_one_device(tiny_run, two_device_run):
    for a, b in zip(params(tiny_run / "checkpoints" / "4"), params(two_device_run), strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=PARAMS_ATOL)
    assert_close(metrics(tiny_run, 4), metrics(two_device_run))
    assert sorted(p.name for p in (two_device_run / "checkpoints").iterdir()) == ["2", "4"]


@pytest.mark.slow  # make test-all: also tests/hostile/test_sources_on_devices.py
def test_two_processes_train_as_two_devices_bit_for_bit(tiny_run, two_device_run, two_process_run):
    for a, b in zip(params(two_device_run), params(two_process_run), strict=True):
        np.testing.assert_array_equal(a, b)
    assert metrics(two_device_run) == metrics(two_process_run)  # process 0 wrote one line per update
    for a, b in zip(params(tiny_run / "checkpoints" / "4"), params(two_process_run), strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=PARAMS_ATOL)
    assert sorted(p.name for p in (two_process_run / "checkpoints").iterdir()) == ["2", "4"]


@pytest.mark.slow  # ~40 s: two processes compile and train
def test_the_primarys_clock_ends_a_budgeted_run_in_every_process(tmp_path, env):
    run_dir = tmp_path / "budget"
    run_ok(processes([*FOUR, "--set", "run.minutes=1e-9", "--run-dir", run_dir], env))  # spent by update 1
    assert [json.loads(line)["update"] for line in (run_dir / "metrics.jsonl").read_text().splitlines()] == [1]
    assert sorted(p.name for p in (run_dir / "checkpoints").iterdir()) == ["1"]


SHORT_SFL = [*SFL, "ppo.total_timesteps=384", "run.checkpoint_every=3"]  # 6 updates, refreshes before 1, 3 and 5


@pytest.mark.slow  # ~50 s: the SFL programs compile for 2 devices; the DR checks above stay in make test
def test_an_sfl_run_on_two_devices_trains_as_on_one_device(tmp_path, env, sfl_run):
    # the first 6 updates of the session's tiny SFL run (1 device; its total steps do not change them: constant
    # lr and entropy weight) against a 6-update run on 2 devices: the losses, entropy and buffer metrics of every
    # update follow from the parameters and buffer before it (the 1-device run has no checkpoint at 6)
    two = tmp_path / "two-devices"
    run_ok([start([*PRETRAIN, *set_args(SHORT_SFL), "--run-dir", two], env, XLA_FLAGS=FORCE_2)])
    assert sfl_config().ppo.anneal_lr is False and sfl_config().ppo.ent_coef_end is None
    one = metrics(sfl_run[1], 6)
    assert "buffer_score" in one[0]  # the buffers' metrics too: scoring split, one buffer
    assert_close(one, metrics(two))


@pytest.mark.parametrize(
    ("victim", "says"),
    [
        # both slow (~55 s each: two processes compile and train); make test keeps the process flags' checks
        pytest.param(1, "error: process 0: process 1 stopped", marks=pytest.mark.slow),
        pytest.param(0, "error: process 1: lost the coordinator (process 0)", marks=pytest.mark.slow),
    ],
    ids=["peer", "coordinator"],
)
def test_a_killed_process_stops_the_other_with_one_line(tmp_path, env, victim, says):
    # `two_process_run`'s command; a process is killed as soon as process 0 has written the run's config, so the
    # other is waiting for it in the run's first steps. Process 1 is seen by the heartbeat watchdog (10 s); process
    # 0 takes the coordination service with it, which jax's runtime answers with an abort and a stack trace,
    # replaced by one line by the supervisor of each process
    run_dir = tmp_path / "killed"
    started = processes([*FOUR, "--run-dir", run_dir], env)
    deadline = time.monotonic() + TIMEOUT
    while not (run_dir / "config.yaml").exists():
        assert time.monotonic() < deadline and all(p.poll() is None for p in started), "did not start"
        time.sleep(0.01)
    os.kill(started[victim].pid, signal.SIGKILL)
    killed = time.monotonic()
    [(code, err)] = finish([started[1 - victim]], timeout=60)
    assert time.monotonic() - killed < 30
    assert code == PEER_LOST_EXIT, err[-2000:]
    lines = err.strip().splitlines()
    assert len(lines) == 1, err[-2000:]
    line = lines[0]
    assert line.startswith(says) and line.endswith(
        "rerun every process with --resume to continue from the last checkpoint"
    )
    started[victim].communicate()


LONGER = ["--set", "ppo.total_timesteps=2560", "--set", "run.checkpoint_every=10", "--set", "run.eval_every=0"]


@pytest.mark.slow
@pytest.mark.parametrize("victim", [0, 1])
def test_kill_9_of_a_process_then_resume_equals_an_uninterrupted_run(tmp_path, env, victim):
    uninterrupted, killed = tmp_path / "uninterrupted", tmp_path / "killed"
    run_ok(processes([*PRETRAIN, *LONGER, "--run-dir", uninterrupted], env))
    started = processes([*PRETRAIN, *LONGER, "--run-dir", killed], env)
    deadline = time.monotonic() + TIMEOUT
    while not (killed / "checkpoints" / "20" / "kinetix-checksums.json").exists():
        assert time.monotonic() < deadline and all(p.poll() is None for p in started), "ended before checkpoint 20"
        time.sleep(0.005)
    os.kill(started[victim].pid, signal.SIGKILL)
    finish(started, timeout=60)  # the other stops (a lost peer or a lost coordinator)
    assert (killed / "checkpoints" / "40").exists() is False
    run_ok(processes([*PRETRAIN, *LONGER, "--run-dir", killed, "--resume"], env))
    for a, b in zip(params(uninterrupted), params(killed), strict=True):
        np.testing.assert_array_equal(a, b)
    assert metrics(killed) == metrics(uninterrupted)


@pytest.mark.parametrize(
    "flags, error",
    [
        (["--devices", "2"], "--devices: must be in 1..1"),
        (["--coordinator", "localhost:1"], "give all three or none"),
        (["--coordinator", "nohost", "--num-processes", "2", "--process-id", "0"], "expected HOST:PORT"),
        (["--coordinator", "localhost:1", "--num-processes", "2", "--process-id", "2"], "must be in 0..1"),
    ],
    ids=["devices", "partial", "address", "process-id"],
)
def test_bad_process_flags_are_one_line(capsys, tmp_path, flags, error):
    from helpers.cli import kinetix

    result = kinetix(capsys, *PRETRAIN, "--run-dir", tmp_path / "run", *flags)
    assert error in result.error_line
    assert not (tmp_path / "run").exists()


def test_envs_that_do_not_split_are_one_line(tmp_path, env):
    odd = ["--set", "ppo.num_envs=3", "--set", "ppo.num_minibatches=1", "--run-dir", tmp_path / "run"]
    [(code, err)] = finish([start([*PRETRAIN, *odd], env, XLA_FLAGS=FORCE_2)])
    expected = "error: ppo.num_envs: 3 does not divide evenly over 2 devices; use a multiple of 2"
    assert code == 2 and err.strip() == expected
    assert not (tmp_path / "run").exists()


@pytest.mark.slow  # ~25 s: a training process of its own; make test checks the choice itself (test_cpu.py)
def test_on_a_default_cpu_split_envs_that_do_not_split_train_on_fewer_devices(tmp_path, env):
    """`kinetix`'s own split (one device per core; 2 here, as `KINETIX_CPU_DEVICES` is unset) never fails a run:
    3 environments train on 1 device, with a warning."""
    odd = [*FOUR, "--set", "ppo.num_envs=3", "--set", "ppo.num_minibatches=1", "--run-dir", tmp_path / "run"]
    script = "from kinetix_cli import cpu; cpu.usable_cores = lambda: 2; from kinetix_cli.cli.app import main; main()"
    unset = {k: v for k, v in env.items() if k != "KINETIX_CPU_DEVICES"}
    done = subprocess.run(
        [sys.executable, "-c", script, *map(str, odd)], env=unset, capture_output=True, text=True, timeout=TIMEOUT
    )
    assert done.returncode == 0, done.stderr
    assert "warning: ppo.num_envs 3 does not split over the 2 CPU devices (one per core); using 1" in done.stderr
