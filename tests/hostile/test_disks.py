"""Writes that fail in the middle of the work (a full disk, a folder that turns read-only) are one line that says
what failed and what was kept, and lose nothing: training keeps its last complete checkpoint and `--resume` ends
where an uninterrupted run does; generation keeps its complete shards and the same command finishes the set;
evaluation keeps its results on the terminal and the old file. On a real small filesystem (`helpers.disks`)."""

from __future__ import annotations

import json
import subprocess

import jax
import numpy as np
import pytest

from helpers.cli import kinetix
from helpers.disks import fill, make_read_only, small_disk
from helpers.levelsets import FILES, small_levelset
from helpers.processes import KINETIX, process_env
from helpers.runs import EVAL_LEVEL, TINY, set_args
from kinetix_cli.errors import WriteError
from kinetix_cli.rl import record as recording
from kinetix_cli.rl.agents import load_policy

PRETRAIN = ["pretrain", "--config", "experiments/cpu-small.yaml", *set_args(TINY)]


def records(run_dir):
    return [{k: v for k, v in json.loads(x).items() if k != "sps"} for x in (run_dir / "metrics.jsonl").open()]


def test_a_full_disk_during_training_keeps_the_last_checkpoint_and_resume_finishes_the_run(
    capfd, monkeypatch, tmp_path, tiny_run
):
    with small_disk(tmp_path / "disk") as disk:
        run = disk / "run"
        save = recording.save_runner

        def fill_before_checkpoint_4(manager, update, runner):
            if update == 4:
                fill(disk)
            save(manager, update, runner)

        monkeypatch.setattr(recording, "save_runner", fill_before_checkpoint_4)
        line = kinetix(capfd, *PRETRAIN, "--run-dir", run).error_line  # one line: orbax's own reports are dropped
        assert line.startswith(f"error: --run-dir {run}: cannot write update 4: No space left on device; ")
        assert line.endswith(
            "the last complete checkpoint (2) is kept; once the folder can be written, rerun with --resume to "
            "continue from it"
        )
        assert sorted(p.name for p in (run / "checkpoints").iterdir()) == ["2"]  # the partial one is gone
        (disk / "filler").unlink()
        monkeypatch.undo()
        result = kinetix(capfd, *PRETRAIN, "--run-dir", run, "--resume")
        assert result.code == 0, result.err
        jax.tree.map(np.testing.assert_array_equal, load_policy(run).params, load_policy(tiny_run).params)
        assert records(run) == records(tiny_run)


@pytest.mark.slow  # a real process compiles and trains (~35 s): the filters it relies on are checked in make test
# (tests/kinetix_cli/rl/test_checkpoints.py), a full disk during training above
def test_a_disk_that_fills_during_a_checkpoint_is_one_line_to_the_end_of_the_process(tmp_path):
    """A real `kinetix pretrain` on a filesystem too small for its first checkpoint, which fails in orbax's array
    writes: the process prints its one line and nothing else, though orbax's writer threads, abandoned asyncio
    tasks and never-run coroutines report their errors later (without the fix: tracebacks and warnings after the
    line in 2 of 2 tries)."""
    with small_disk(tmp_path / "disk", size="120k") as disk:
        # 120 KB: less than the first checkpoint (2), so orbax's own writes fail, not a file of ours
        args = [*PRETRAIN, *set_args(["ppo.total_timesteps=1920", "run.eval_every=0"]), "--run-dir", disk / "run"]
        done = subprocess.run([*KINETIX, *map(str, args)], env=process_env(), capture_output=True, text=True)
    assert done.returncode == 2, done.stderr[-2000:]
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("error: --run-dir "), done.stderr[-3000:]
    assert "cannot write update 2: no space left on the device" in done.stderr


def test_a_folder_that_turns_read_only_while_generating_keeps_the_complete_shards(tmp_path):
    whole = small_levelset(tmp_path / "whole", shard_size=2)
    with small_disk(tmp_path / "disk") as disk:
        turned = []

        def read_only_after_shard_0(index):
            if index == 2 and not turned:  # levels 0 and 1 (shard 0) are written
                make_read_only(disk)
                turned.append(index)

        with pytest.raises(WriteError) as failed:
            small_levelset(disk / "set", shard_size=2, per_chunk=1, before_chunk=read_only_after_shard_0)
        message = str(failed.value)
        assert f"{disk / 'set' / 'shard-00001.npz'}: cannot be created: {disk / 'set'} is not writable; " in message
        assert message.endswith(
            "the 2 levels of the 1 complete shards are kept; once the folder can be written, rerun the same command "
            "to continue"
        )
        subprocess.run(["mount", "-o", "remount,rw", str(disk)], check=True)
        finished = small_levelset(disk / "set", shard_size=2, per_chunk=1)
        assert finished["shards"] == whole["shards"] and finished["count"] == len(FILES)


def test_a_full_disk_when_eval_writes_its_json_keeps_the_results_and_the_old_file(capfd, tmp_path, tiny_run):
    with small_disk(tmp_path / "disk") as disk:
        out = disk / "eval.json"
        out.write_text("the old results")
        fill(disk)
        result = kinetix(capfd, "eval", tiny_run, "--levels", EVAL_LEVEL, "--attempts", "3", "--json", out)
        line = result.error_line
        assert f"--json {out}: cannot write: No space left on device; the results are in the table above" in line
        assert line.endswith(f"{out} is unchanged")
        assert "rocket-car-jump" in result.out  # the table was printed before the write
        assert out.read_text() == "the old results"
        assert sorted(p.name for p in disk.iterdir()) == ["eval.json", "filler"]  # no temporary left
