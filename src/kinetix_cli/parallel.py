"""Devices and processes, on JAX's own machinery: a 1-D device mesh over the batch, `jax.distributed` for
several processes.

Training, scoring and evaluation are written for one global batch (of environments, levels, attempts) and run
on a `Mesh` whose one axis `BATCH` splits that batch across devices; parameters, optimiser state and level pools
are replicated. The programs are the same at every device count: sharding only annotates them
(`batch_sharded` inside jitted code, `shard_batch` / `replicate` for their inputs) and XLA inserts the
collectives (the gradient all-reduce, gathers of drawn levels). Random numbers are drawn for the global batch
(`jax_threefry_partitionable`, on by default), so the draws do not depend on how the batch is split.

Several processes (one per host, or several on one host) join with `initialize` before anything else touches
JAX; each drives its local devices, the mesh spans all of them, and only the primary process (`is_primary`)
writes the run's files.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import subprocess
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterator

import jax
import numpy as np
from jax.sharding import AxisType, Mesh, NamedSharding, PartitionSpec

from kinetix_cli import cpu
from kinetix_cli.errors import UserError

BATCH = "batch"
"""The mesh axis that splits batches (environments, levels, attempts) across devices."""
SPLIT = PartitionSpec(BATCH)
"""`per_device`: an argument or result split along its leading axis over the devices."""
COPY = PartitionSpec()
"""`per_device`: an argument with a full copy on every device."""

PEER_TIMEOUT = 10.0
"""A process whose heartbeat has not changed for this long is taken as dead, and the others stop [s]."""
BEAT = 1.0
"""Seconds between heartbeats."""
PEER_LOST_EXIT = 3
"""Exit code of a process that stops because another process of its run died (rerun all with --resume)."""
_SERVICE_HEARTBEAT = 60
"""jax.distributed's own heartbeat timeout [s]: longer than `PEER_TIMEOUT`, so the watchdog's one clear line
comes before the runtime's abort (a C++ check failure and stack trace)."""


def fitting_devices(sizes: dict[str, int]) -> int | None:
    """Local devices for work that splits batches of these global `sizes` (setting -> size) when the user named no
    count: None (all of them), except on a CPU split by default (`cpu.split`, one process), where it is the most
    devices every size splits over evenly, with a warning when that is fewer than all. (A count the user chose is
    checked by `check_divisible` instead: one clear error.)"""
    local = jax.local_devices()
    if cpu.automatic() is None or local[0].platform != "cpu":
        return None
    count = max(n for n in range(1, len(local) + 1) if all(size % n == 0 for size in sizes.values()))
    if count < len(local):
        odd = ", ".join(f"{what} {size}" for what, size in sizes.items() if size % len(local))
        message = f"{odd} does not split over the {len(local)} CPU devices (one per core); using {count}"
        warnings.warn(message, stacklevel=2)
    return count


def initialize(coordinator: str | None, num_processes: int | None, process_id: int | None) -> None:
    """Join a multi-process run (`jax.distributed.initialize`) on the CPU collectives of gloo (GPUs use NCCL).

    All three None: a single process, unless a cluster is detected as `jax.distributed` does it (SLURM, ...)
    when `KINETIX_DISTRIBUTED=auto` is set. Otherwise `coordinator` is HOST:PORT of process 0 and every process
    passes the same `num_processes` and its own `process_id`."""
    given = [coordinator is not None, num_processes is not None, process_id is not None]
    auto = os.environ.get("KINETIX_DISTRIBUTED", "") == "auto"
    if not any(given) and not auto:
        return
    if any(given) and not all(given):
        raise UserError("--coordinator, --num-processes and --process-id: give all three or none")
    if all(given):
        if num_processes < 1:
            raise UserError(f"--num-processes: must be at least 1, got {num_processes}")
        if not 0 <= process_id < num_processes:
            raise UserError(f"--process-id: must be in 0..{num_processes - 1}, got {process_id}")
        host, _, port = coordinator.rpartition(":")
        if not host or not port.isdigit():
            raise UserError(f"--coordinator: expected HOST:PORT, got {coordinator!r}")
    cpu.unsplit()  # several processes: each keeps the one CPU device XLA gives it, unless told otherwise
    if auto or num_processes > 1:
        _supervised(process_id)
    jax.config.update("jax_cpu_collectives_implementation", "gloo")
    jax.config.update("jax_enable_preemption_service", False)  # TPU preemption notices: not used here
    try:
        jax.distributed.initialize(
            coordinator_address=coordinator,
            num_processes=num_processes,
            process_id=process_id,
            initialization_timeout=120,
            heartbeat_timeout_seconds=_SERVICE_HEARTBEAT,
            shutdown_timeout_seconds=30,
        )
    except Exception as exc:  # jax raises RuntimeError / ValueError / XlaRuntimeError for the same failures
        message = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise UserError(f"--coordinator {coordinator}: cannot join the run: {message}") from None
    if jax.process_count() > 1:
        threading.Thread(target=_watch, name="kinetix-peers", daemon=True).start()
        _connect_devices()


def _connect_devices() -> None:
    """Run one collective over every device now, while the processes are together (they just met in
    `jax.distributed.initialize`): it sets up the CPU collectives' connections between them, which give up when a
    peer comes more than 30 s after the first; the later collectives of the run then wait for a late peer."""
    from jax.experimental import multihost_utils

    multihost_utils.sync_global_devices("kinetix: connect the devices")


def failed(exc: BaseException) -> None:
    """In a multi-process run, what to do with an error that is not the user's (a collective whose peer is gone
    raises one): give the heartbeat watchdog the time to name the process that stopped, else stop with the
    error's first line. Returns at once in a single process (the caller re-raises)."""
    if jax.process_count() == 1 or isinstance(exc, UserError | KeyboardInterrupt):
        return
    time.sleep(PEER_TIMEOUT + 3 * BEAT)
    reason = str(exc).strip().splitlines()[0][:200] if str(exc).strip() else type(exc).__name__
    _stop(f"process {jax.process_index()}: a step shared with the other processes failed ({reason})")


def finish() -> None:
    """Tell the other processes that this one ended normally (its heartbeat stopping is no failure)."""
    _finished.set()
    client = _client()
    if client is not None:
        with contextlib.suppress(Exception):
            client.key_value_set(f"kinetix/done/{jax.process_index()}", "1", allow_overwrite=True)


_finished = threading.Event()


def _client():
    from jax._src import distributed  # the runtime client jax.distributed.initialize made (no public accessor)

    return distributed.global_state.client


def _watch() -> None:
    """Heartbeats through jax.distributed's key-value store; stop this process with one line when a peer's
    heartbeat stops (it died or failed) or the coordinator cannot be reached. A process blocked in a collective
    with a dead peer would otherwise wait for the runtime's timeout and abort with a stack trace."""
    client, me, count = _client(), jax.process_index(), jax.process_count()
    last: dict[int, tuple[str, float]] = {}
    beat = 0
    while not _finished.is_set():
        beat += 1
        now = time.monotonic()
        try:
            client.key_value_set(f"kinetix/alive/{me}", str(beat), allow_overwrite=True)
            alive = dict(client.key_value_dir_get("kinetix/alive/"))
            done = dict(client.key_value_dir_get("kinetix/done/"))
        except Exception:  # the coordinator (process 0) is gone
            if _finished.is_set():
                return
            _stop(f"process {me}: lost the coordinator (process 0); the run stopped")
        for peer in range(count):
            value = alive.get(f"kinetix/alive/{peer}")
            if peer == me or f"kinetix/done/{peer}" in done:
                continue
            if peer not in last or last[peer][0] != value:
                last[peer] = (value, now)
            elif now - last[peer][1] > PEER_TIMEOUT and not _finished.is_set():
                _stop(f"process {me}: process {peer} stopped (no heartbeat for {PEER_TIMEOUT:.0f} s); the run stopped")
        time.sleep(BEAT)


def _stop(line: str) -> None:
    sys.stderr.write(f"error: {line}; rerun every process with --resume to continue from the last checkpoint\n")
    sys.stderr.flush()
    os._exit(PEER_LOST_EXIT)


_SUPERVISOR = "KINETIX_SUPERVISOR"
"""Set in the worker process that `_supervised` starts: its supervisor's pid."""
_RUNTIME_ABORT = (
    "Polled an error from coordination service",
    "Terminating process because the JAX distributed service detected fatal errors",
)
"""How jax's runtime starts the messages with which it aborts a process whose coordinator (process 0) is gone."""


def _supervised(process_id: int | None) -> None:
    """Run this command in a worker process under a small supervisor (this process), which passes the worker's
    stderr through and exits with its code, except for one case: when process 0 dies, jax's runtime aborts the
    others with a fatal message and a C++ stack trace (no Python hook can replace it in jax 0.10.2); the
    supervisor prints one line instead and exits with `PEER_LOST_EXIT`. Returns in the worker; never returns in
    the supervisor. The worker dies with its supervisor (Linux: PR_SET_PDEATHSIG), so killing either kills both."""
    if os.environ.get(_SUPERVISOR):  # the worker
        if sys.platform == "linux":
            ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
        if str(os.getppid()) != os.environ[_SUPERVISOR]:  # the supervisor died before that
            os._exit(PEER_LOST_EXIT)
        return
    env = os.environ | {_SUPERVISOR: str(os.getpid())}
    worker = subprocess.Popen(sys.orig_argv, env=env, stderr=subprocess.PIPE, text=True, errors="replace")
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C reaches the worker from the terminal itself
    signal.signal(signal.SIGTERM, lambda signum, frame: worker.send_signal(signum))
    aborted = False
    for line in worker.stderr:
        aborted = aborted or any(text in line for text in _RUNTIME_ABORT)
        if not aborted:  # the abort message and its stack trace are dropped
            sys.stderr.write(line)
            sys.stderr.flush()
    code = worker.wait()
    if aborted and code != 0:  # (a worker that still ended well keeps its own exit code)
        who = "" if process_id is None else f"process {process_id}: "
        _stop(f"{who}lost the coordinator (process 0); the run stopped")
    os._exit(code if code >= 0 else 128 - code)


def process_index() -> int:
    """This process's index in the run (0 in a single process)."""
    return jax.process_index()


def process_count() -> int:
    """Processes in the run (1 without `initialize`)."""
    return jax.process_count()


def is_primary() -> bool:
    """True in the process that writes the run's files (process 0; the only one without `initialize`)."""
    return jax.process_index() == 0


BARRIER_TIMEOUT = 24 * 3600
"""How long `sync` waits for the other processes [s]: as long as their work before it may take (compiling, a pool
being generated); a process that died stops the others through the heartbeat watchdog instead."""


def sync(name: str) -> None:
    """Wait until every process of a multi-process run gets here (a no-op in a single process). A barrier of
    jax.distributed's coordination service, not a collective on the devices: the CPU collectives (gloo) give up
    when a peer is 30 s late to their first use, and a peer can be later than that (compiling what this process
    read from its compile cache)."""
    if jax.process_count() > 1:
        _barriers[name] = _barriers.get(name, 0) + 1  # a barrier id is used once
        _client().wait_at_barrier(f"kinetix/{name}/{_barriers[name]}", BARRIER_TIMEOUT * 1000)


_barriers: dict[str, int] = {}


def primary_decides(name: str, value: bool) -> bool:
    """The primary process's `value` in every process (a single process: `value`): for decisions each process
    would make differently, like a wall-clock budget each one times on its own clock. Every process must call it
    at the same points, each call with a new (`name`, count); passed through jax.distributed's key-value store."""
    if jax.process_count() == 1:
        return value
    _barriers[name] = _barriers.get(name, 0) + 1
    key = f"kinetix/decide/{name}/{_barriers[name]}"
    if is_primary():
        _client().key_value_set(key, "1" if value else "0")
        return value
    return _client().blocking_key_value_get(key, BARRIER_TIMEOUT * 1000) == "1"


def make_mesh(devices: int | None = None, local_only: bool = False) -> Mesh:
    """The 1-D mesh over `devices` local devices of every process (None: all of them); with `local_only`, over
    this process's only (work that each process does on its own, like evaluation)."""
    local = jax.local_devices()
    if devices is not None and not 1 <= devices <= len(local):
        raise UserError(f"--devices: must be in 1..{len(local)} (the local {local[0].platform} devices), got {devices}")
    count = len(local) if devices is None else devices  # every process takes its first `count` devices
    processes = [jax.process_index()] if local_only else range(jax.process_count())
    chosen = [d for p in processes for d in _process_devices(p)[:count]]
    return jax.make_mesh((len(chosen),), (BATCH,), (AxisType.Auto,), devices=chosen)


def _process_devices(process: int) -> list:
    return sorted((d for d in jax.devices() if d.process_index == process), key=lambda d: d.id)


def check_divisible(count: int, mesh: Mesh, what: str) -> None:
    """A clear error unless `count` (the global size of a batch axis, named by `what`) splits evenly."""
    devices = mesh.size
    if count % devices:
        raise UserError(f"{what}: {count} does not divide evenly over {devices} devices; use a multiple of {devices}")


def batch_sharded(tree, axis: int = 0):
    """Inside jitted code under `using(mesh)`: the leaves of `tree` split along their axis `axis` (the batch)
    over the mesh. A no-op without a mesh, so the same functions run unsharded."""
    spec = PartitionSpec(*([None] * axis), BATCH)
    return _constrain(tree, spec)


def replicated(tree):
    """Inside jitted code under `using(mesh)`: a full copy of every leaf of `tree` on each device."""
    return _constrain(tree, PartitionSpec())


def per_device(fn: Callable, in_specs: tuple, out_specs=SPLIT) -> Callable:
    """Inside jitted code under `using(mesh)`: `fn` run by each device on its own part of the batch
    (`jax.shard_map`; each argument `SPLIT` or `COPY`), its results joined along the batch. For work whose size
    or branch depends on the data (a `lax.cond`, a count of rows), so that it holds no collective: XLA's CPU
    runtime orders collectives by when they start, and a branch whose collectives start late can meet another
    collective on its way and stall both devices (seen as an abort after 40 s;
    `tests/kinetix_cli/rl/test_collectives.py`). Without a mesh (or on one device): `fn` itself."""
    mesh = jax.sharding.get_abstract_mesh()
    if mesh.empty or mesh.size == 1:
        return fn
    return jax.shard_map(fn, in_specs=in_specs, out_specs=out_specs)


def _constrain(tree, spec: PartitionSpec):
    mesh = jax.sharding.get_abstract_mesh()
    if mesh.empty or mesh.size == 1:
        return tree
    return jax.tree.map(lambda x: jax.lax.with_sharding_constraint(x, spec), tree)


@contextlib.contextmanager
def using(mesh: Mesh) -> Iterator[Mesh]:
    """Run (and trace) jitted code under `mesh`, so `batch_sharded` applies."""
    with jax.set_mesh(mesh):
        yield mesh


def replicate(tree, mesh: Mesh):
    """Every leaf (host or device array) as a global array with a full copy on each device of the mesh. In a
    multi-process run every process must pass equal values."""
    sharding = NamedSharding(mesh, PartitionSpec())
    return jax.tree.map(lambda x: _global(x, sharding), tree)


def shard_batch(tree, mesh: Mesh):
    """Every leaf as a global array split along its leading axis over the mesh (equal values in every process)."""
    sharding = NamedSharding(mesh, PartitionSpec(BATCH))
    return jax.tree.map(lambda x: _global(x, sharding), tree)


def pad_batch(tree, multiple: int):
    """Host arrays padded along their leading axis, by repeating the last row, to a multiple of `multiple`
    (a batch of independent items that must split evenly; the caller drops the padding's results)."""

    def pad(x):
        x = np.asarray(x)
        extra = -len(x) % multiple
        return np.concatenate([x, np.repeat(x[-1:], extra, axis=0)]) if extra else x

    return jax.tree.map(pad, tree)


def _global(x, sharding: NamedSharding):
    if isinstance(x, jax.Array) and x.sharding == sharding:
        return x
    if isinstance(x, jax.Array) and not x.is_fully_addressable:  # a global array of another layout (made under
        return _reshard(x, sharding)  # a mesh): device_put only moves arrays this process holds whole
    if jax.dtypes.issubdtype(getattr(x, "dtype", None), jax.dtypes.prng_key):
        data = np.asarray(jax.random.key_data(x))
        impl = jax.random.key_impl(x)
        return jax.random.wrap_key_data(_global(data, sharding), impl=impl)
    host = np.asarray(x)
    return jax.make_array_from_callback(host.shape, sharding, lambda index: host[index])


def _reshard(x: jax.Array, sharding: NamedSharding) -> jax.Array:
    """A global array laid out as `sharding`, by XLA's collectives (every process calls this with its part)."""
    return jax.jit(lambda a: a, out_shardings=sharding)(x)
