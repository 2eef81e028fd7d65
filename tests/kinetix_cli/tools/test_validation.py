"""The validation suite's tools: `kinetix validation build --check` rebuilds the shipped held-out levels byte for byte
(compiled as `kinetix` compiles), and `kinetix validation run` writes a record of every part with its scores."""

from __future__ import annotations

import subprocess

import pytest

from helpers.cli import kinetix
from helpers.processes import KINETIX, TIMEOUT, release_env
from kinetix_cli.tools.validation import FINETUNE_LEVELS, read_validation


@pytest.mark.slow
def test_a_rebuild_writes_the_shipped_held_out_levels():
    done = subprocess.run(
        [*KINETIX, "validation", "build", "--check", "--sizes", "s"],
        env=release_env(),
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert done.returncode == 0 and "are what a rebuild writes" in done.stdout, done.stdout + done.stderr


@pytest.mark.slow
def test_a_validation_run_records_each_part(capsys, tiny_run, tmp_path):
    out = tmp_path / "validation.json"
    quick = ["--set", "ppo.total_timesteps=2048"]  # one update per fine-tuning run
    args = ["validation", "run", tiny_run, "--json", out, "--attempts", "1", "--finetune-seeds", "0", *quick]
    result = kinetix(capsys, *args)
    assert result.code == 0 and "validation: held out" in result.out, result.out
    record = read_validation(out)
    assert record["suites"]["all"]["levels"] == 180 and record["attempts"] == 1
    assert set(record["score"]) == {"heldout", "ours", "zero_shot", "finetune"}
    assert len(record["finetune"]["levels"]) == len(FINETUNE_LEVELS)
    assert "ppo.total_timesteps=2048" in record["finetune"]["settings"]  # a quick look says so
    assert all(row["seeds"] == [0] and len(row["solve_rate"]) == 1 for row in record["finetune"]["levels"].values())
    assert "jax" in record["versions"]["versions"]
