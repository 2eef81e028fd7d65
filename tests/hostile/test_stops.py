"""A scheduler's SIGTERM to `kinetix pretrain` mid-run: the process finishes the update in flight, saves it as a
checkpoint, says so in one line and exits with 143 (128 + SIGTERM); resumed, the run ends with the parameters and
metrics of an uninterrupted one. A real process, signalled as soon as it has logged its first update."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time

import jax
import numpy as np
import pytest

from helpers.processes import KINETIX, TIMEOUT, process_env
from helpers.runs import TINY, set_args, tiny_config
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.train import train

LONG = ["ppo.total_timesteps=1920", "run.checkpoint_every=100", "run.eval_every=0"]  # 30 updates of the tiny run


def records(run_dir) -> list[dict]:
    return [{k: v for k, v in json.loads(x).items() if k != "sps"} for x in (run_dir / "metrics.jsonl").open()]


# ~45 s: three kinetix processes; make test keeps SIGTERM and Ctrl-C mid-run in-process (rl/test_record.py)
@pytest.mark.slow
def test_sigterm_mid_run_checkpoints_the_update_in_flight_and_resume_matches_an_uninterrupted_run(tmp_path, tiny_pool):
    cut, whole = tmp_path / "cut", tmp_path / "whole"
    args = ["pretrain", "--config", "experiments/cpu-small.yaml", *set_args([*TINY, *LONG]), "--run-dir", cut]
    process = subprocess.Popen(
        [*KINETIX, *map(str, args)], env=process_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    metrics, deadline = cut / "metrics.jsonl", time.monotonic() + TIMEOUT
    while not (metrics.exists() and metrics.stat().st_size):
        assert process.poll() is None and time.monotonic() < deadline, process.communicate()[1][-2000:]
        time.sleep(0.002)
    os.kill(process.pid, signal.SIGTERM)
    _, err = process.communicate(timeout=TIMEOUT)

    assert process.returncode == 128 + signal.SIGTERM, err[-2000:]
    stopped_at = len(records(cut))
    assert 1 <= stopped_at < 30  # the signal came mid-run
    assert err.strip().splitlines()[-1] == (
        f"stopped by SIGTERM after update {stopped_at}: checkpoint {stopped_at} is saved; rerun with --resume to "
        "continue from it"
    )
    assert sorted(int(p.name) for p in (cut / "checkpoints").iterdir()) == [stopped_at]

    config = tiny_config(*LONG)
    resumed = train(config, cut, resume=True, pool=tiny_pool)
    uninterrupted = train(config, whole, pool=tiny_pool)
    assert records(cut) == records(whole)
    jax.tree.map(np.testing.assert_array_equal, resumed.params, uninterrupted.params)
    jax.tree.map(np.testing.assert_array_equal, load_policy(cut).params, load_policy(whole).params)
