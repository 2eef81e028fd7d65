"""Runs and checkpoints: a start that fails writes nothing, a resume after a crash before the first checkpoint or
with a torn metrics line ends as an uninterrupted run, and a damaged, mismatched or missing checkpoint is one
line. Every run is the tiny run (`helpers.runs`)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import jax
import numpy as np
import pytest
import yaml

from helpers.cli import kinetix
from helpers.runs import EVAL_LEVEL, TINY, set_args, tiny_config
from kinetix_cli.errors import UserError
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.checkpoints import CHECKSUMS_FILE
from kinetix_cli.rl.train import train


class Crash(Exception):
    pass


def crash_at(update):
    def progress(record):
        if record["update"] == update:
            raise Crash

    return progress


def records(run_dir):
    return [{k: v for k, v in json.loads(x).items() if k != "sps"} for x in (run_dir / "metrics.jsonl").open()]


@pytest.fixture
def copy_of(tmp_path, tiny_run):
    def make(name="copy"):
        return shutil.copytree(tiny_run, tmp_path / name)

    return make


def test_resume_after_a_crash_before_the_first_checkpoint_restarts_cleanly(tmp_path, tiny_run, tiny_pool):
    with pytest.raises(Crash):
        train(tiny_config(), tmp_path / "run", pool=tiny_pool, progress=crash_at(1))
    assert not (tmp_path / "run" / "checkpoints" / "2").exists() and len(records(tmp_path / "run")) == 1
    resumed = train(tiny_config(), tmp_path / "run", resume=True, pool=tiny_pool)
    assert records(tmp_path / "run") == records(tiny_run)  # no duplicated line 1
    jax.tree.map(np.testing.assert_array_equal, resumed.params, load_policy(tiny_run).params)


def test_a_torn_last_metrics_line_is_dropped_on_resume(tmp_path, tiny_run, tiny_pool):
    with pytest.raises(Crash):
        train(tiny_config(), tmp_path / "run", pool=tiny_pool, progress=crash_at(3))
    with open(tmp_path / "run" / "metrics.jsonl", "a") as f:
        f.write('{"update": 4, "steps": 2')  # killed in the middle of a write
    train(tiny_config(), tmp_path / "run", resume=True, pool=tiny_pool)
    assert records(tmp_path / "run") == records(tiny_run)


def test_a_flipped_byte_in_the_array_data_is_caught_before_orbax_reads_it(capsys, copy_of):
    run = copy_of()
    data = max((run / "checkpoints" / "6").rglob("d/*"), key=lambda p: p.stat().st_size)
    raw = bytearray(data.read_bytes())
    raw[len(raw) // 2] ^= 0xFF
    data.write_bytes(bytes(raw))
    line = kinetix(capsys, "eval", run, "--levels", EVAL_LEVEL).error_line
    assert f"checkpoints/6: {data.relative_to(run / 'checkpoints' / '6')} does not match its checksum" in line


def test_a_truncated_or_missing_checkpoint_is_one_line(capsys, copy_of):
    run = copy_of()
    for data in (run / "checkpoints" / "6").rglob("d/*"):
        data.write_bytes(data.read_bytes()[:10])
    assert "does not match its checksum; the checkpoint is damaged" in kinetix(capsys, "eval", run).error_line
    next((run / "checkpoints" / "6").rglob("d/*")).unlink()
    assert "is missing; the checkpoint is incomplete" in kinetix(capsys, "eval", run).error_line
    shutil.rmtree(run / "checkpoints")
    line = kinetix(capsys, "eval", run).error_line
    assert "no checkpoint" in line and not (run / "checkpoints").exists()  # reading creates nothing


def test_damaged_checksums_are_one_line(capsys, copy_of):
    run = copy_of()
    (run / "checkpoints" / "6" / CHECKSUMS_FILE).write_text('{"format": "kinetix-checksums/1"}')
    assert "files: missing; the checksums of this checkpoint are damaged" in kinetix(capsys, "eval", run).error_line
    (run / "checkpoints" / "6" / CHECKSUMS_FILE).write_text('{"format": "kinetix-checksums/9", "files": {}}')
    assert "format: expected 'kinetix-checksums/1'" in kinetix(capsys, "eval", run).error_line


def test_a_config_that_does_not_match_the_checkpoint(capsys, copy_of, tiny_pool):
    run = copy_of()
    saved = yaml.safe_load((run / "config.yaml").read_text())
    saved["model"]["width"] = 32
    (run / "config.yaml").write_text(yaml.safe_dump(saved))
    assert "do not fit the model" in kinetix(capsys, "eval", run).error_line
    wider = tiny_config("model.width=32")
    with pytest.raises(UserError, match="checkpoints/6: written with other model or PPO settings than this run's"):
        train(wider, run, resume=True, pool=tiny_pool)


FAILED_STARTS = [
    (["pretrain"], ["--levels", "{TMP}/no-set"], "no-set"),
    (["pretrain"], ["--set", "run.eval_levels=[levels/nowhere]"], "levels/nowhere: no such file"),
    (["pretrain"], ["--set", "run.init_from={TMP}/no-run"], "no-run: not a run directory"),
    (["finetune", EVAL_LEVEL, "--from", "{TMP}/no-run"], [], "no-run: not a run directory"),
    (["pretrain"], ["--set", "model.width=32", "--set", "run.init_from={RUN}"], "does not match this run's model"),
]


@pytest.mark.parametrize(("command", "extra", "message"), FAILED_STARTS, ids=lambda x: " ".join(x)[:40])
def test_a_start_that_fails_writes_nothing(capsys, tmp_path, tiny_run, command, extra, message):
    run = tmp_path / "run"
    args = [*command, "--config", "experiments/cpu-small.yaml", "--run-dir", run, *set_args(TINY), *extra]
    line = kinetix(capsys, *(str(a).format(TMP=tmp_path, RUN=tiny_run) for a in args)).error_line
    assert message in line and not run.exists()


def test_the_corrected_command_then_runs(capsys, tmp_path):
    run = tmp_path / "run"
    args = ["pretrain", "--config", "experiments/cpu-small.yaml", "--run-dir", run, *set_args(TINY)]
    assert "no-set" in kinetix(capsys, *args, "--levels", tmp_path / "no-set").error_line
    result = kinetix(capsys, *args)
    assert result.code == 0, result.err
    assert (run / "checkpoints" / "6").is_dir()


def test_a_damaged_checkpoint_is_one_line_in_a_real_process(copy_of):
    """Orbax's failed reads leave callbacks that print tracebacks when the process exits; the CLI drops them."""
    run = copy_of()
    for data in (run / "checkpoints" / "6").rglob("d/*"):
        data.write_bytes(data.read_bytes()[:10])
    command = [sys.executable, "-c", "from kinetix_cli.cli.app import main; main()", "eval", str(run)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert "does not match its checksum" in done.stderr
