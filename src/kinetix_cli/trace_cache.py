"""Traced programs kept on disk across processes: `cached_jit` is `jax.jit` for the big programs of a run (a
training update, SFL's scoring, an evaluator), whose trace a later process reads back instead of tracing again.

Why: JAX's persistent compilation cache (`kinetix_cli.compile_cache`) skips XLA's compile, but every process still
traces and lowers each program, and for the training update that is most of a repeated command's time (a repeat of
the general recipe's 16K-step run: tracing and lowering took 90 of its 119 s under the profiler). A program here is
exported once (`jax.export`: its StableHLO, input and output types and shardings) and written to disk; a later call
with the same key deserialises it, and its compile comes from the compile cache.

The key of a program names everything its trace depends on: the function (module and name), the source of the
`kinetix_cli` and `engine` packages (a hash of every `.py` file: any edit starts new entries), the static arguments
(their pickled bytes, a flax module by its class and fields: `static_bytes`), the structure, shapes, dtypes and
shardings of the traced arguments, the ambient mesh, the versions of Python and of the libraries whose code is
traced (`LIBRARIES`), the backend and its devices, and the jax settings that change a trace. A program whose static
arguments cannot be pickled, that is called inside another trace, that jax cannot export, or that runs over several
processes (`jax.distributed`) is traced as `jax.jit` traces it.

`compiling` compiles programs in threads while other work runs, for the calls that follow (SFL's update loads while
its refresh loads and scores: a process's first update waits on neither load alone).

Entries are Python pickles (the output's tree structure and the serialised program): like JAX's compiled programs
beside them, they are trusted as the user's own files.

Where: the `traces` folder inside the compile cache's folder, on or off with it (`KINETIX_COMPILE_CACHE=off`;
`KINETIX_TRACE_CACHE=off` turns off the traces alone: the test suite does, see tests/conftest.py). Each
entry is one file, written atomically with a format version; the folder is bounded (`MAX_BYTES`, least recently
used first). An entry that cannot be read (damaged, another format, another key) is a miss: the program is traced
again and the entry written anew, without a word.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import dataclasses
import functools
import hashlib
import inspect
import io
import os
import pickle
import sys
import tempfile
import time
from collections.abc import Callable
from importlib.metadata import version
from pathlib import Path
from typing import Any

FORMAT = "kinetix-trace/1"
"""Format of an entry; an entry of another format is a miss."""
FOLDER = "traces"
"""The traces' folder inside the compile cache's (`kinetix_cli.compile_cache`)."""
VARIABLE = "KINETIX_TRACE_CACHE"
"""Environment variable: `off` keeps traces off while the compile cache is on."""
SUFFIX = ".trace"
MAX_BYTES = 2**30
"""The folder's size bound: beyond it, the least recently used entries are removed after a write."""
STALE_SECONDS = 3600
"""A temporary file this old belongs to a write that was stopped (a live write renames its file within seconds)."""
SETTINGS = (
    "jax_enable_x64",
    "jax_default_matmul_precision",
    "jax_default_prng_impl",
    "jax_threefry_partitionable",
    "jax_numpy_rank_promotion",
    "jax_numpy_dtype_promotion",
    "jax_disable_most_optimizations",
)
"""jax settings that a trace (or its key's meaning) depends on."""
PACKAGES = ("kinetix_cli", "engine")
"""The packages whose source is part of every key."""
LIBRARIES = ("jax", "jaxlib", "flax", "optax", "numpy")
"""The installed libraries whose versions are part of every key (their code is traced too)."""

_folder: Path | None = None
_memory: dict[str, tuple[Callable, Any] | None] = {}
"""This process's programs by key: the jitted call and the output's tree structure (None: not exportable)."""


def enable(folder: Path | None) -> None:
    """Keep traces in `folder` (None: off, every call traced as `jax.jit` traces it). Imports nothing: a command
    that computes nothing does not pay for jax."""
    global _folder
    _folder = folder
    _memory.clear()


def folder_in(compile_folder: Path | None) -> Path | None:
    """The traces' folder inside the compile cache's `compile_folder`; None when that is off or `VARIABLE` says
    `off`."""
    if compile_folder is None or os.environ.get(VARIABLE, "").strip().lower() == "off":
        return None
    return compile_folder / FOLDER


def folder() -> Path | None:
    """The folder traces are kept in, None when off."""
    return _folder


@functools.cache
def source_hash() -> str:
    """A hash of every `.py` file of `PACKAGES`, by path and content."""
    digest = hashlib.sha256()
    for package in PACKAGES:
        root = Path(__import__(package).__file__).parent
        for path in sorted(root.rglob("*.py")):
            digest.update(str(path.relative_to(root.parent)).encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()


@functools.cache
def process_key() -> str:
    """The part of every key that is fixed for a process: the format, the source, the versions of Python and
    `LIBRARIES`, the backend and its devices (computed once: a training run calls its update thousands of times)."""
    import jax

    devices = jax.devices()
    parts = [
        FORMAT,
        source_hash(),
        sys.version,
        *(f"{name}={version(name)}" for name in LIBRARIES),
        f"{devices[0].platform} {devices[0].device_kind} {len(devices)} {jax.process_count()}",
    ]
    return "\0".join(parts)


def static_bytes(static: dict[str, Any]) -> bytes:
    """The static arguments' part of a key: their pickle, by name, with each flax module written as its class and
    its fields. A module's own pickle holds its creation number in the process (flax's `_id`), so an equal network
    built after other modules (as in a test suite, or by another command) would give another key."""
    buffer = io.BytesIO()
    _StaticPickler(buffer, protocol=5).dump(sorted(static.items()))
    return buffer.getvalue()


class _StaticPickler(pickle.Pickler):
    def reducer_override(self, obj):
        linen = sys.modules.get("flax.linen")  # no flax imported: no module to find
        if linen is not None and isinstance(obj, linen.Module):
            fields = [(f.name, getattr(obj, f.name)) for f in dataclasses.fields(obj) if f.name != "parent"]
            return _module, (type(obj), fields)
        return NotImplemented


def _module(cls, fields):
    """Stands for a module in `static_bytes` (never called: keys are not read back)."""
    return cls(**dict(fields))


def cached_jit(fun: Callable | None = None, *, static_argnums=(), static_argnames=()):
    """`jax.jit(fun, static_argnums=..., static_argnames=...)` whose trace is kept on disk when `enable`d; usable
    as a decorator with or without arguments. The returned function also has `lower` (of what its call runs) and
    `jax.jit`'s `trace`."""
    if fun is None:
        return functools.partial(cached_jit, static_argnums=static_argnums, static_argnames=static_argnames)
    return TracedProgram(fun, static_argnums, static_argnames)


class TracedProgram:
    """A jitted function whose traced program is kept on disk (`cached_jit`)."""

    def __init__(self, fun: Callable, static_argnums, static_argnames):
        import jax

        numbers = (static_argnums,) if isinstance(static_argnums, int) else tuple(static_argnums)
        names = (static_argnames,) if isinstance(static_argnames, str) else tuple(static_argnames)
        self.fun = fun
        self.jitted = jax.jit(fun, static_argnums=numbers, static_argnames=names)
        self.signature = inspect.signature(fun)
        parameters = list(self.signature.parameters)
        self.static = frozenset(names) | {parameters[i] for i in numbers}
        self.plain = any(p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD) for p in self.signature.parameters.values())
        self.name = f"{fun.__module__}.{fun.__qualname__}"
        functools.update_wrapper(self, fun)

    def trace(self, *args, **kwargs):
        return self.jitted.trace(*args, **kwargs)

    def __call__(self, *args, **kwargs):
        import jax

        found = self._program(args, kwargs)
        if found is None:
            return self.jitted(*args, **kwargs)
        call, out_tree, leaves = found
        return jax.tree.unflatten(out_tree, call(*leaves))

    def _program(self, args: tuple, kwargs: dict) -> tuple[Callable, Any, list] | None:
        """The jitted call of the exported program for these arguments (read from disk, or traced and written on
        first use), its output's tree structure and the traced arguments' leaves; None where the call is
        `jax.jit`'s own (traces off, over several processes, inside another trace, no key, not exportable)."""
        import jax
        import jax.numpy as jnp

        if _folder is None or self.plain or jax.process_count() > 1:  # (runs over processes: not measured)
            return None
        bound = self.signature.bind(*args, **kwargs)
        bound.apply_defaults()
        static = {k: v for k, v in bound.arguments.items() if k in self.static}
        traced = {k: v for k, v in bound.arguments.items() if k not in self.static}
        leaves, tree = jax.tree.flatten(traced)
        if any(isinstance(leaf, jax.core.Tracer) for leaf in leaves):
            return None  # inside another trace: part of that program
        leaves = [leaf if isinstance(leaf, jax.Array) else jnp.asarray(leaf) for leaf in leaves]
        try:
            statics = static_bytes(static)
        except Exception:  # a static argument without a stable byte form: no key
            return None
        key = self._key(statics, tree, leaves)
        if key not in _memory:
            _memory[key] = _read(key) or self._export(key, static, tree, leaves)
        if _memory[key] is None:  # jax could not export it
            return None
        call, out_tree = _memory[key]
        return call, out_tree, leaves

    def lower(self, *args, **kwargs):
        """The program a call with these arguments runs, lowered (`jax.stages.Lowered`; with traces on, the exported
        program read back or traced): compiling it compiles what the call will run (`compiling`)."""
        found = self._program(args, kwargs)
        if found is None:
            return self.jitted.lower(*args, **kwargs)
        call, _, leaves = found
        return call.lower(*leaves)

    def _key(self, statics: bytes, tree, leaves: list) -> str:
        import jax

        digest = hashlib.sha256()
        parts = [
            self.name,
            process_key(),
            str(tree),
            repr(jax.sharding.get_abstract_mesh()),
            *(f"{name}={jax.config.values.get(name)}" for name in SETTINGS),
            *(f"{jax.typeof(leaf)} {leaf.sharding!r}" for leaf in leaves),
        ]
        for part in parts:
            digest.update(part.encode() + b"\0")
        digest.update(statics)
        return digest.hexdigest()

    def _export(self, key: str, static: dict, tree, leaves: list) -> tuple[Callable, Any] | None:
        """Trace and export the program, write its entry; None when jax cannot export it (traced as `jax.jit`
        traces it from then on)."""
        import jax

        trees = []

        def flat(*leaves):
            out = self.fun(**jax.tree.unflatten(tree, leaves), **static)
            out_leaves, out_tree = jax.tree.flatten(out)
            trees.append(out_tree)
            return out_leaves

        flat.__name__ = self.fun.__name__  # the program keeps the function's name (XLA's dumps, profiles)
        try:
            exported = jax.export.export(jax.jit(flat))(*leaves)
        except Exception:  # something jax cannot export (or a bad input, which the plain call raises again)
            return None
        _write(key, exported, trees[0])
        return _caller(exported, self.fun.__name__), trees[0]


def _caller(exported, name: str) -> Callable:
    """The jitted call of an exported program, named after its function."""
    import jax

    def call(*leaves):
        return exported.call(*leaves)

    call.__name__ = name
    return jax.jit(call)


def _read(key: str) -> tuple[Callable, Any] | None:
    """The entry of `key` from disk, or None when missing or unreadable."""
    import jax

    path = _folder / f"{key}{SUFFIX}"
    try:
        entry = pickle.loads(path.read_bytes())
        if entry["format"] != FORMAT or entry["key"] != key:
            return None
        exported = jax.export.deserialize(entry["exported"])
        out_tree = jax.tree.structure(entry["out"])
        if out_tree.num_leaves != len(exported.out_avals):
            return None
        with contextlib.suppress(OSError):
            os.utime(path)  # recently used
        return _caller(exported, entry["name"]), out_tree
    except Exception:  # missing, damaged, written by other code: traced again
        return None


def _write(key: str, exported, out_tree) -> None:
    """Write an entry atomically, then keep the folder within `MAX_BYTES`; a failure to write is ignored."""
    import jax

    entry = {
        "format": FORMAT,
        "key": key,
        "name": exported.fun_name,
        "out": jax.tree.unflatten(out_tree, list(range(out_tree.num_leaves))),
        "exported": bytes(exported.serialize()),
    }
    with contextlib.suppress(Exception):
        _folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=_folder, prefix=".", suffix=".tmp", delete=False) as f:
            pickle.dump(entry, f, protocol=5)
        os.replace(f.name, _folder / f"{key}{SUFFIX}")
        _bound(_folder, _folder / f"{key}{SUFFIX}")


def _bound(folder: Path, kept: Path) -> None:
    """Remove the least recently used entries but `kept` (the one just written) while the folder holds more than
    `MAX_BYTES`, and the temporary files of writes stopped before their rename (`STALE_SECONDS` old)."""
    for temporary in folder.glob(".*.tmp"):
        with contextlib.suppress(OSError):
            if time.time() - temporary.stat().st_mtime > STALE_SECONDS:
                temporary.unlink()
    entries = []
    for path in folder.glob(f"*{SUFFIX}"):
        with contextlib.suppress(OSError):
            stat = path.stat()
            entries.append((stat.st_mtime, stat.st_size, path))
    total = sum(size for _, size, _ in entries)
    for _, size, path in sorted(entries):
        if total <= MAX_BYTES:
            break
        if path == kept:
            continue
        with contextlib.suppress(OSError):
            path.unlink()
        total -= size


@contextlib.contextmanager
def compiling(*calls: functools.partial):
    """Compile the programs of `calls` (each a `cached_jit` function with its arguments) in threads of their own
    while the block runs, and wait for them when it ends: the calls that follow find their programs compiled (jax
    keeps what it compiled; a program compiled before is found there at once). Nothing of them runs; a call that
    cannot be lowered or compiled here is left to itself (the call raises what it raises).

    Why: a command's first call of each big program waits on its compile, from the compile cache a load of
    seconds (a training update's: its HLO module rebuilt, its executable linked) on one core. A program loaded
    while the block loads and runs another uses the core that leaves idle; without a cache the compiles overlap
    the same way."""
    lowered = []
    for call in calls:  # lowered here: a trace sees this thread's settings (the mesh)
        with contextlib.suppress(Exception):
            lowered.append(call.func.lower(*call.args, **call.keywords))
    with concurrent.futures.ThreadPoolExecutor(max(len(lowered), 1)) as pool:
        compiles = [pool.submit(step.compile) for step in lowered]
        yield
        for compile_ in compiles:
            with contextlib.suppress(Exception):
                compile_.result()
