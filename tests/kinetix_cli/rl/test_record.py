"""Recording a run: a stop signal ends it after the update in flight, checkpointed, and `--resume` continues it bit
for bit; a second signal acts at once and keeps the last complete checkpoint; the signals' own handlers are back
after the run. Every run is the tiny run (`helpers.runs`); the signals are sent by the run's own progress callback,
so each arrives after a known update."""

from __future__ import annotations

import json
import os
import signal

import jax
import numpy as np
import pytest

from helpers.runs import tiny_config
from kinetix_cli.errors import Stopped
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.train import train


def records(run_dir) -> list[dict]:
    return [{k: v for k, v in json.loads(x).items() if k != "sps"} for x in (run_dir / "metrics.jsonl").open()]


def checkpoints(run_dir) -> list[str]:
    return sorted(p.name for p in (run_dir / "checkpoints").iterdir())


def signal_after(update: int, signum: int, times: int = 1):
    def progress(record):
        if record["update"] == update:
            for _ in range(times):
                os.kill(os.getpid(), signum)

    return progress


@pytest.fixture
def default_sigint():
    """SIGINT raises KeyboardInterrupt during the test, as in a terminal (a test worker may ignore it)."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


# make test stops with SIGTERM (a scheduler's); SIGINT (Ctrl-C) takes the same path, runs in make test-all (~9 s
# here), and the two tests below stop with SIGINT in make test
STOPS = [pytest.param(signal.SIGINT, marks=pytest.mark.slow), signal.SIGTERM]


@pytest.mark.parametrize("signum", STOPS, ids=lambda s: signal.Signals(s).name)
def test_a_stopped_run_saves_the_update_in_flight_and_resumes_bit_identically(
    tmp_path, tiny_run, tiny_pool, default_sigint, signum
):
    run = tmp_path / "run"
    handlers = [signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)]
    with pytest.raises(Stopped) as stopped:
        train(tiny_config(), run, pool=tiny_pool, progress=signal_after(4, signum))
    name = signal.Signals(signum).name
    assert str(stopped.value) == (
        f"stopped by {name} after update 5: checkpoint 5 is saved; rerun with --resume to continue from it"
    )
    assert stopped.value.exit_code == 128 + signum
    assert [signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)] == handlers
    assert checkpoints(run) == ["2", "4", "5"]  # 5: the update in flight when the signal came
    assert [r["update"] for r in records(run)] == [1, 2, 3, 4, 5]
    assert records(run) == records(tiny_run)[:5]  # no evaluation added at the stop

    resumed = train(tiny_config(), run, resume=True, pool=tiny_pool)
    assert records(run) == records(tiny_run)
    jax.tree.map(np.testing.assert_array_equal, resumed.params, load_policy(tiny_run).params)


def test_a_second_signal_stops_at_once_and_keeps_the_last_complete_checkpoint(
    tmp_path, tiny_run, tiny_pool, default_sigint
):
    run = tmp_path / "run"
    with pytest.raises(KeyboardInterrupt):
        train(tiny_config(), run, pool=tiny_pool, progress=signal_after(3, signal.SIGINT, times=2))
    assert checkpoints(run) == ["2"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    resumed = train(tiny_config(), run, resume=True, pool=tiny_pool)
    jax.tree.map(np.testing.assert_array_equal, resumed.params, load_policy(tiny_run).params)


def test_a_signal_after_the_last_update_ends_the_run_as_usual(tmp_path, tiny_run, tiny_pool, default_sigint):
    run = tmp_path / "run"
    train(tiny_config(), run, pool=tiny_pool, progress=signal_after(6, signal.SIGINT))
    assert records(run) == records(tiny_run)
