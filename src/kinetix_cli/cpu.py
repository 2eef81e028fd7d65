"""The CPU as JAX devices. XLA's CPU backend gives a process one device, which keeps about 1.25 cores busy; with
one device per core, the commands that batch their work (training, evaluation, generation) split it over all of
them (`kinetix_cli.parallel`). `kinetix` splits the CPU this way before JAX starts (`split`); GPUs are not affected.

`KINETIX_CPU_DEVICES=N` chooses the count (1: one device, JAX's default). A count chosen for JAX itself (XLA_FLAGS'
`--xla_force_host_platform_device_count`, `JAX_NUM_CPU_DEVICES`) is left as it is. Read without importing jax (a
command that computes nothing does not pay for it).
"""

from __future__ import annotations

import os
import sys

from kinetix_cli.errors import UserError

VARIABLE = "KINETIX_CPU_DEVICES"
"""Environment variable: how many JAX devices `kinetix` splits the CPU into."""
MAX_DEVICES = 4
"""The most CPU devices of the default split (one per core up to this). Measured: 2 devices on a 2-core CPU train
1.2-1.4x faster than 1 (BENCHMARKS.md, "Training throughput per device count"); more cores were not measured."""
JAX_VARIABLE = "JAX_NUM_CPU_DEVICES"
"""JAX's own environment variable for the count (its config `jax_num_cpu_devices`)."""

_automatic: int | None = None
"""The count `split` chose by default in this process (None: none, or the user's)."""
_set_variable = False
"""Whether `split` set `JAX_VARIABLE` (jax was not imported yet)."""


def split() -> int | None:
    """Give JAX one CPU device per usable core, at most `MAX_DEVICES`, or `KINETIX_CPU_DEVICES` of them, unless a
    count is chosen for JAX itself or its backend has started. Returns the count set, or None."""
    global _automatic, _set_variable
    chosen = os.environ.get(VARIABLE, "").strip()
    if chosen and not (chosen.isdigit() and int(chosen) >= 1):
        raise UserError(f"{VARIABLE}={chosen!r}: expected a whole number of CPU devices, at least 1")
    if _backend_started() or _chosen_for_jax():
        return None
    count = int(chosen) if chosen else default_count()
    if "jax" in sys.modules:
        sys.modules["jax"].config.update("jax_num_cpu_devices", count)
    else:
        os.environ[JAX_VARIABLE] = str(count)
        _set_variable = True
    _automatic = None if chosen else count
    return count


def automatic() -> int | None:
    """The CPU device count `split` chose by default in this process (None: no split, or the user's count)."""
    return _automatic


def unsplit() -> None:
    """Undo a default split before JAX's backend starts (a multi-process run keeps XLA's own count per process);
    processes started from this one no longer inherit it."""
    global _automatic, _set_variable
    if _automatic is None:
        return
    if _set_variable:
        os.environ.pop(JAX_VARIABLE, None)
        _set_variable = False
    if "jax" in sys.modules:
        sys.modules["jax"].config.update("jax_num_cpu_devices", -1)  # XLA's own count: XLA_FLAGS, else 1
    _automatic = None


def default_count() -> int:
    """The default split: one device per usable core, at most `MAX_DEVICES`."""
    return min(usable_cores(), MAX_DEVICES)


def usable_cores() -> int:
    """Cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def _chosen_for_jax() -> bool:
    if "xla_force_host_platform_device_count" in os.environ.get("XLA_FLAGS", ""):
        return True
    if "jax" in sys.modules:
        return sys.modules["jax"].config.jax_num_cpu_devices >= 0
    return bool(os.environ.get(JAX_VARIABLE, "").strip())


def _backend_started() -> bool:
    if "jax" not in sys.modules:
        return False
    from jax._src import xla_bridge  # (no public accessor)

    return xla_bridge.backends_are_initialized()
