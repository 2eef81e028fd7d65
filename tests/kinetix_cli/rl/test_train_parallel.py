"""Training across devices and processes gives the run of one device: the tiny run (6 updates, evaluations and
checkpoints included) on 1 device (in this process), on 2 forced host devices in one process, and as 2
processes of one device each on localhost (gloo collectives). And a killed peer stops the others with one line.

The 2-device program splits every batch and averages the gradient with an all-reduce, so its sums run in
another order than the 1-device program's: parameters agree to float32 rounding (1e-6 after 6 updates), not
bit for bit. 2 devices in one process and 2 processes run the same partitioned program: bit for bit equal."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import jax
import numpy as np
import pytest

from helpers.runs import TINY, set_args
from kinetix_cli.parallel import PEER_LOST_EXIT
from kinetix_cli.rl.checkpoints import load_policy

KINETIX = [sys.executable, "-c", "from kinetix_cli.cli.app import main; main()"]
PRETRAIN = ["pretrain", "--config", "experiments/cpu-small.yaml", *set_args(TINY)]
TIMEOUT = 600  # [s] a bound on every process: a hang fails the test instead of stalling the suite


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def env(tmp_path_factory):
    """A shared compile cache (the processes of one run compile the same programs)."""
    return os.environ | {"JAX_COMPILATION_CACHE_DIR": str(tmp_path_factory.mktemp("jax-cache"))}


def start(args: list, env: dict, **extra) -> subprocess.Popen:
    return subprocess.Popen(
        [*KINETIX, *map(str, args)], env=env | extra, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )


def finish(processes: list[subprocess.Popen], timeout: float = TIMEOUT) -> list[tuple[int, str]]:
    """Wait for every process (killing all of them if one outlives `timeout`); (exit code, stderr) of each."""
    deadline = time.monotonic() + timeout
    results = []
    try:
        for process in processes:
            _, err = process.communicate(timeout=max(deadline - time.monotonic(), 1))
            results.append((process.returncode, err))
    finally:
        for process in processes:
            process.kill()
    return results


def processes(args: list, env: dict, count: int = 2) -> list[subprocess.Popen]:
    coordinator = f"localhost:{free_port()}"
    flags = ["--coordinator", coordinator, "--num-processes", str(count)]
    return [start([*args, *flags, "--process-id", str(i)], env) for i in range(count)]


@pytest.fixture(scope="module")
def two_device_run(tmp_path_factory, env):
    run_dir = tmp_path_factory.mktemp("parallel") / "two-devices"
    [(code, err)] = finish([start([*PRETRAIN, "--run-dir", run_dir], env, XLA_FLAGS=FORCE_2)])
    assert code == 0, err[-2000:]
    return run_dir


FORCE_2 = "--xla_force_host_platform_device_count=2"


@pytest.fixture(scope="module")
def two_process_run(tmp_path_factory, env):
    run_dir = tmp_path_factory.mktemp("parallel") / "two-processes"
    for code, err in finish(processes([*PRETRAIN, "--run-dir", run_dir], env)):
        assert code == 0, err[-2000:]
    return run_dir


def params(run_dir: Path) -> list[np.ndarray]:
    return jax.tree.leaves(load_policy(run_dir)[1])


def metrics(run_dir: Path) -> list[dict]:
    lines = (run_dir / "metrics.jsonl").read_text().splitlines()
    return [{k: v for k, v in json.loads(line).items() if k != "sps"} for line in lines]


def test_two_devices_train_as_one(tiny_run, two_device_run):
    for a, b in zip(params(tiny_run), params(two_device_run), strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-6)
    one, two = metrics(tiny_run), metrics(two_device_run)
    assert [r.keys() for r in one] == [r.keys() for r in two]
    for a, b in zip(one, two, strict=True):
        np.testing.assert_allclose([a[k] for k in a], [b[k] for k in a], rtol=1e-4, atol=1e-6)
    assert sorted(p.name for p in (two_device_run / "checkpoints").iterdir()) == ["2", "4", "6"]


def test_two_processes_train_as_two_devices(two_device_run, two_process_run):
    for a, b in zip(params(two_device_run), params(two_process_run), strict=True):
        np.testing.assert_array_equal(a, b)
    assert metrics(two_device_run) == metrics(two_process_run)
    # only process 0 wrote the run's files: one line per update, and every checkpoint verified
    assert [r["update"] for r in metrics(two_process_run)] == [1, 2, 3, 4, 5, 6]


def test_a_killed_peer_stops_the_other_with_one_line(tmp_path, env, two_process_run):
    # the same run as `two_process_run` (its compiles are in the cache); process 1 is killed as soon as process 0
    # has written the run's config, so process 0 is waiting for it in the run's first steps
    run_dir = tmp_path / "killed"
    first, second = processes([*PRETRAIN, "--run-dir", run_dir], env)
    deadline = time.monotonic() + TIMEOUT
    while not (run_dir / "config.yaml").exists():
        assert time.monotonic() < deadline and first.poll() is None and second.poll() is None, "did not start"
        time.sleep(0.01)
    os.kill(second.pid, signal.SIGKILL)
    killed = time.monotonic()
    [(code, err)] = finish([first], timeout=60)
    assert time.monotonic() - killed < 30
    assert code == PEER_LOST_EXIT, err[-2000:]
    last = err.strip().splitlines()[-1]
    assert last.startswith("error: process 0: process 1 stopped") and "--resume" in last, err[-2000:]
    assert "Traceback" not in err, err[-2000:]
    second.communicate()


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
