"""Checkpoint writes: what a failed write leaves behind on the terminal. (The real full disk, in a real process:
tests/hostile/test_disks.py.)"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import warnings

import pytest

from helpers.processes import FORCE_2, process_env
from kinetix_cli.rl import checkpoints
from kinetix_cli.rl.checkpoints import PARTIAL, checkpoint_manager, writing


class Seen(logging.Handler):
    def __init__(self):
        super().__init__()
        self.messages = []

    def emit(self, record):
        self.messages.append(record.getMessage())


def full_disk_in(filename: str) -> OSError:
    """A full disk's OSError (its message names no folder) raised by code in `filename`."""
    scope = {}
    exec(compile("def write():\n    raise OSError(28, 'No space left on device')\n", filename, "exec"), scope)
    try:
        scope["write"]()
    except OSError as error:
        return error


def reported(name: str, *errors: BaseException) -> list[str]:
    """What logger `name`'s records reach a handler, of one asyncio-style report per error and a plain error."""
    logger, seen = logging.getLogger(name), Seen()
    logger.addHandler(seen)
    try:
        for i, error in enumerate(errors):
            logger.error(
                f"Future exception was never retrieved {i}", exc_info=(type(error), error, error.__traceback__)
            )
        logger.error("an error of another kind")
    finally:
        logger.removeHandler(seen)
    return seen.messages


@pytest.mark.parametrize("name", ["absl", "asyncio"])
def test_reports_of_an_unfinished_write_are_dropped_after_the_block_and_others_are_not(tmp_path, name):
    # orbax's writer threads (absl) and abandoned asyncio tasks report a failed write at any later moment
    with writing(checkpoint_manager(tmp_path / "run")):
        pass
    logger, seen = logging.getLogger(name), Seen()
    logger.addHandler(seen)
    try:
        logger.error(f"Error writing {tmp_path}/run/checkpoints/2{PARTIAL}-1733/ocdbt: RESOURCE_EXHAUSTED")
        try:
            raise ValueError(f"RESOURCE_EXHAUSTED: {tmp_path}/checkpoints/4{PARTIAL}-9")
        except ValueError:
            logger.exception("Task exception was never retrieved")
        logger.error("an error of another kind")
    finally:
        logger.removeHandler(seen)
    assert seen.messages == ["an error of another kind"]


def test_after_a_failed_write_orbaxs_own_errors_are_dropped_and_others_are_not(tmp_path, monkeypatch):
    # a write task's bare "No space left on device", reported by asyncio when collected (seen in 1 of 5 real runs)
    monkeypatch.setattr(checkpoints._UnfinishedWrites, "failed", False)
    orbax = full_disk_in(f"{os.sep}site-packages{os.sep}orbax{os.sep}checkpoint{os.sep}async_path.py")
    ours = full_disk_in(f"{os.sep}src{os.sep}kinetix_cli{os.sep}io.py")
    assert len(reported("asyncio", orbax, ours)) == 3  # no write has failed: everything is reported
    with pytest.raises(OSError), writing(checkpoint_manager(tmp_path / "run")):
        raise OSError(28, "No space left on device")
    assert reported("asyncio", orbax, ours) == ["Future exception was never retrieved 1", "an error of another kind"]


def test_after_a_failed_write_the_never_awaited_coroutines_are_quiet(tmp_path):
    with pytest.raises(OSError), writing(checkpoint_manager(tmp_path / "run")):
        raise OSError(28, "No space left on device")
    with warnings.catch_warnings(record=True) as caught:
        warnings.warn("coroutine 'write_chunk' was never awaited", RuntimeWarning, stacklevel=1)
        warnings.warn("another warning", RuntimeWarning, stacklevel=1)
    assert [str(w.message) for w in caught] == ["another warning"]


SAVE_ON_2_DEVICES = """
import sys

import jax
import jax.numpy as jnp
import numpy as np
import orbax.checkpoint as ocp
from jax.sharding import NamedSharding, PartitionSpec

from kinetix_cli.rl.checkpoints import checkpoint_manager

mesh = jax.make_mesh((2,), ("batch",))
state = {"weights": jnp.arange(12.0).reshape(3, 4), "count": jnp.arange(5), "rows": jnp.arange(8.0)}
spec = {"weights": PartitionSpec(), "count": PartitionSpec(), "rows": PartitionSpec("batch")}
placed = jax.block_until_ready({k: jax.device_put(v, NamedSharding(mesh, spec[k])) for k, v in state.items()})
compiles = []
jax.monitoring.register_event_duration_secs_listener(
    lambda event, seconds, **_: compiles.append(event) if event.endswith("backend_compile_duration") else None
)
with checkpoint_manager(sys.argv[1]) as manager:
    manager.save(1, args=ocp.args.StandardSave(placed))
    manager.wait_until_finished()
    saving = len(compiles)
    back = manager.restore(1, args=ocp.args.StandardRestore(placed))
print(saving, all(np.array_equal(back[k], state[k]) for k in state))
"""


def test_a_save_on_2_devices_compiles_nothing_and_reads_back(tmp_path):
    """Replicated arrays are written whole by one replica (orbax's replica-parallel write slices their shards with
    small compiled programs: about a second of every new process's first save of the general recipe's state); a
    sharded one as before. The checkpoint reads back equal."""
    env = process_env() | {"XLA_FLAGS": FORCE_2}
    done = subprocess.run(
        [sys.executable, "-c", SAVE_ON_2_DEVICES, str(tmp_path)], env=env, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split() == ["0", "True"], "compiles while saving, read back equal"
