"""Checkpoint writes: what a failed write leaves behind on the terminal. (The real full disk, in a real process:
tests/hostile/test_disks.py.)"""

from __future__ import annotations

import logging
import os
import warnings

import pytest

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
