"""What made a file: the toolkit's version, the library versions and the machine (for runs, level sets and
benchmarks)."""

from __future__ import annotations

import datetime
import os
import platform
from importlib import metadata

import jax

from kinetix_cli import __version__

LIBRARIES = ("jax", "jaxlib", "flax", "optax", "orbax-checkpoint", "numpy", "gymnax", "gymnasium", "jax2d")


def tool_version() -> str:
    """The installed `kinetix` version; run from a checkout's `src/` without installing (as on a lent GPU), the
    package's own `__version__` marked "(source)"."""
    try:
        return metadata.version("kinetix")
    except metadata.PackageNotFoundError:
        return f"{__version__} (source)"


def environment_info() -> dict:
    """Date, machine, device and library versions, for the record."""
    versions = {"kinetix": tool_version()}
    for package in LIBRARIES:
        try:
            versions[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            versions[package] = None
    device = jax.devices()[0]
    return {
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "machine": {
            "platform": platform.platform(),
            "processor": platform.processor() or platform.machine(),
            "cpu_count": os.cpu_count(),
            "device": f"{device.platform}:{device.device_kind}",
        },
        "versions": versions,
    }
