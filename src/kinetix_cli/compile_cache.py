"""JAX's persistent compilation cache, on for every `kinetix` command: a program compiled once (a training run's
update, an evaluator, the generator) is read back from disk by the next process that compiles it, instead of
compiled again. Tracing a program still happens in every process; only XLA's compile is skipped.

Where: `$XDG_CACHE_HOME/kinetix/jax/<key>` (else `~/.cache/kinetix/jax/<key>`). The key names what a compiled
program depends on beyond its own text: the versions of Python, jax and jaxlib, and the processor (model and
instruction-set flags), so an upgrade or another machine sharing the home folder starts a folder of its own and never
reads a foreign entry. `KINETIX_COMPILE_CACHE=DIR` puts it in DIR; `KINETIX_COMPILE_CACHE=off` turns it off. (JAX's
own `JAX_COMPILATION_CACHE_DIR`, when set, is used as JAX documents it: its folder, or off when empty.)

Safety: the folder is bounded (`MAX_BYTES`, least recently used entries evicted), and every read and write takes
the folder's file lock (`filelock`), so processes compiling at the same time never read an entry half written. A
damaged entry is read as a miss: the program is compiled again and nothing is printed. An entry without its access
time (`NAME-cache` without `NAME-atime`: its process was killed while writing it, or a cache without a size bound
wrote it) is removed when a command starts (`remove_unfinished`): JAX's eviction reads every entry's access time
before each write, so one such entry made every later write fail, silently (seen here: a killed test process left
one, and the suite's folder stopped growing). A folder copied or moved elsewhere is read as empty: JAX's key of an
entry includes the folder's own path (seen with jax 0.10.2: a copy of a warm folder compiled everything again).
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import platform
import sys
import warnings
from importlib.metadata import version
from pathlib import Path

import filelock

VARIABLE = "KINETIX_COMPILE_CACHE"
"""Environment variable: a folder for the cache, or `off`."""
MAX_BYTES = 4 * 2**30
"""The cache folder's size bound: beyond it, the least recently used entries are removed."""
CACHE_SUFFIX, ATIME_SUFFIX = "-cache", "-atime"
"""The two files of an entry of JAX's bounded cache: the compiled program and the time it was last used."""
MIN_COMPILE_S = 0.5
"""Programs that compile faster than this are not written (the many small programs of op-by-op code)."""


def machine_key() -> str:
    """A short hash of the versions of Python, jax and jaxlib and of the processor (model and flags), read without
    importing jax (a command that compiles nothing does not pay for it)."""
    jax, jaxlib = version("jax"), version("jaxlib")
    cpu = ""
    with contextlib.suppress(OSError):
        lines = Path("/proc/cpuinfo").read_text().splitlines()
        cpu = "\n".join(sorted({line for line in lines if line.startswith(("model name", "flags"))}))
    what = f"{sys.version} {jax} {jaxlib} {platform.machine()} {cpu}"
    return f"jax-{jax}-{hashlib.sha256(what.encode()).hexdigest()[:16]}"


def cache_folder() -> Path | None:
    """The cache folder: `KINETIX_COMPILE_CACHE` if set (None when it says `off`), else `JAX_COMPILATION_CACHE_DIR`
    if set (None when empty), else `user_folder("jax")`."""
    chosen = os.environ.get(VARIABLE, "").strip()
    if chosen.lower() == "off":
        return None
    if chosen:
        return Path(chosen).expanduser()
    if "JAX_COMPILATION_CACHE_DIR" in os.environ:
        return Path(os.environ["JAX_COMPILATION_CACHE_DIR"]) if os.environ["JAX_COMPILATION_CACHE_DIR"] else None
    return user_folder("jax")


def user_folder(name: str) -> Path:
    """`kinetix/NAME/<machine_key()>` in the user's cache folder (`$XDG_CACHE_HOME`, else `~/.cache`)."""
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "kinetix" / name / machine_key()


def enable(folder: Path | None) -> None:
    """Compile through the persistent cache in `folder` (None: leave it off), with its size bound and file lock.
    Before jax is imported this sets JAX's environment variables (which processes started from this one inherit),
    after it JAX's config."""
    if folder is None:
        return
    settings = {
        "jax_compilation_cache_dir": str(folder),
        "jax_persistent_cache_min_compile_time_secs": MIN_COMPILE_S,
        "jax_compilation_cache_max_size": MAX_BYTES,  # turns on JAX's eviction and its file lock
    }
    remove_unfinished(folder)
    for name, value in settings.items():
        if "jax" in sys.modules:
            sys.modules["jax"].config.update(name, value)
        else:
            os.environ[name.upper()] = str(value)
    # a damaged entry is a miss and compiles again: nothing to tell
    warnings.filterwarnings("ignore", message="Error (reading|writing) persistent compilation cache entry")


LOCK_TIMEOUT_S = 10
"""How long `remove_unfinished` waits for the folder's lock (JAX's own wait) before leaving the folder as it is."""


def remove_unfinished(folder: Path) -> list[Path]:
    """Remove the entries of JAX's cache `folder` that have no access-time file (see the module's docstring), under
    the folder's lock, so no entry another process is writing is touched. Returns the removed files."""
    if not folder.is_dir():
        return []
    removed = []
    with contextlib.suppress(filelock.Timeout), filelock.FileLock(folder / ".lockfile", timeout=LOCK_TIMEOUT_S):
        for entry in folder.glob(f"*{CACHE_SUFFIX}"):
            if not entry.with_name(entry.name.removesuffix(CACHE_SUFFIX) + ATIME_SUFFIX).exists():
                entry.unlink(missing_ok=True)
                removed.append(entry)
    return removed
