"""A small real filesystem for the tests of failed writes: a tmpfs mounted in the test's folder (root only, as the
suite runs in CI), filled to the last byte on demand, or made read-only."""

from __future__ import annotations

import contextlib
import os
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

SIZE = "8m"
"""Room for the tiny run's config, metrics and a few checkpoints (~300 KB each)."""


@contextlib.contextmanager
def small_disk(folder: Path, size: str = SIZE) -> Iterator[Path]:
    """A fresh tmpfs of `size` (default `SIZE`) mounted at `folder` (created) for the block; skips the test where
    this process cannot mount one (not root, or a container that forbids it)."""
    folder.mkdir(parents=True, exist_ok=True)
    if os.geteuid() != 0:
        pytest.skip("mounting a small filesystem needs root (CI runs as root)")
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)], capture_output=True)
    if mounted.returncode:
        pytest.skip(f"cannot mount a tmpfs here: {mounted.stderr.decode().strip()}")
    try:
        yield folder
    finally:
        subprocess.run(["umount", "-l", str(folder)], check=False)


def fill(disk: Path) -> Path:
    """Write a file that takes every free byte of `disk`; deleting it frees the space again."""
    filler = disk / "filler"
    with open(filler, "wb", buffering=0) as f:
        for size in (65536, 1):  # then byte by byte into the last partial block
            with contextlib.suppress(OSError):
                while f.write(b"\0" * size):
                    pass
    return filler


def make_read_only(disk: Path) -> None:
    """Remount `disk` read-only (every later write fails with EROFS)."""
    subprocess.run(["mount", "-o", "remount,ro", str(disk)], check=True)
