"""Starting a run: every batch a run splits across devices, named by the setting that sets it (the one-line errors
on devices: tests/kinetix_cli/rl/test_train_parallel.py; the fallback of a default CPU split: tests/kinetix_cli/
test_cpu.py)."""

from __future__ import annotations

import dataclasses

from helpers.runs import SFL, tiny_config
from kinetix_cli.rl.launch import split_sizes


def test_every_batch_a_run_splits_is_named_by_its_setting():
    plain = tiny_config()
    assert split_sizes(plain.ppo, plain.clone, plain.curriculum) == {"ppo.num_envs": 8}
    sfl = tiny_config(*SFL, "curriculum.score_attempts=3")
    cloning = dataclasses.replace(sfl.clone, levels="solved-set", updates=1, batch=12)
    assert split_sizes(sfl.ppo, cloning, sfl.curriculum) == {
        "ppo.num_envs": 8,
        "curriculum.score_levels": 8,
        "clone.batch": 12,
    }
