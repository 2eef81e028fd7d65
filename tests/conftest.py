"""Pytest configuration. Helpers live in tests/helpers (on the path): sim.py shares compiled engine rollouts,
runs.py the tiny training runs, whose pool and finished run directories are session fixtures here."""

from __future__ import annotations

import gc
import os
import shutil
from pathlib import Path

import hypothesis
import jax
import pytest
from filelock import FileLock

from helpers.levelsets import CHUNK
from helpers.processes import FAST_CODEGEN, FAST_COMPILE
from helpers.runs import sfl_config, tiny_config
from kinetix_cli import compile_cache, cpu, trace_cache
from kinetix_cli.generator.filters import generate_chunk, make_config
from kinetix_cli.rl.pool import level_pool
from kinetix_cli.rl.train import train


def _compile_cache() -> Path:
    """JAX's persistent compilation cache for the suite: one folder for both xdist workers and every `kinetix` process
    a test starts, so a program compiled once (the tiny run's update, a CLI command's evaluator) is read back by the
    others instead of compiled again. It only skips XLA's compile: tracing, and so every check of what is traced or
    how often, is unchanged.

    The folder is the user's, as `kinetix`'s own (`kinetix_cli.compile_cache`), under `kinetix/jax-tests/<key>`
    (the suite compiles with other flags), so every checkout on the machine shares it and a fresh clone's `make test`
    reads what an earlier run compiled; the key (versions and processor) starts a new folder after an upgrade.
    `KINETIX_TEST_CACHE=DIR` puts it elsewhere (`make test KINETIX_TEST_CACHE=$(mktemp -d)` measures a cold run);
    `make clean` leaves it."""
    override = os.environ.get("KINETIX_TEST_CACHE")
    return Path(override) if override else compile_cache.user_folder("jax-tests")


COMPILE_CACHE = _compile_cache()


# FAST_COMPILE (helpers.processes) is set for the suite and every process it starts: XLA skips most of its
# optimisation work (LLVM at -O0, no expensive passes; JAX's own switch for programs whose compile costs more than
# their run). The suite's programs are tiny, so compile time dominates it: the tiny run compiles in 18 s instead of
# 30, a generated pool in 23 instead of 43. Each operation is IEEE float32 either way (no fast-math), but fusion and
# pass order differ, so a long contact-rich episode can round its way to another ending: the runs compared bit for
# bit are all compiled this way, and recorded level solutions are replayed as `kinetix` compiles
# (`helpers.processes.release_env`).
#
# KINETIX_TEST_CODEGEN=release (`make test KINETIX_TEST_CODEGEN=release`) sets neither FAST_CODEGEN nor
# FAST_COMPILE: the suite and every process it starts compile as `kinetix` compiles outside the suite (XLA's default
# CPU code generation and optimisations). Slower; it checks the suite's float tolerances against other last-bit
# rounding, as another CPU rounds. Unset (or "fast"): the settings above.

CODEGEN = "KINETIX_TEST_CODEGEN"
"""Environment variable choosing how the suite compiles: "fast" (the default) or "release"."""


def pytest_configure(config):
    codegen = os.environ.get(CODEGEN, "fast") or "fast"
    if codegen not in ("fast", "release"):
        raise pytest.UsageError(f'{CODEGEN}={codegen!r}: expected "fast" or "release"')
    # One CPU device for the suite and every process it starts, as JAX's default: the runs it compares bit for bit
    # were made that way, and XLA_FLAGS' forced device count still gives a test's process 2. `kinetix` itself
    # splits the CPU into one device per core (tests/kinetix_cli/test_cpu.py).
    os.environ[cpu.VARIABLE] = "1"
    os.environ[compile_cache.VARIABLE] = str(COMPILE_CACHE)  # started `kinetix` processes inherit it
    # Tracing, not compiling, is most of the suite's JAX time (a full make test here: 520 s tracing and 280 s
    # lowering against 240 s of XLA compile, summed over workers), and tracing makes many short-lived objects: with
    # Python's garbage collector run less often, the tiny run's update traces and lowers ~8% faster (4.6-4.9 s
    # against 5.1-5.2 s here).
    gc.set_threshold(50_000, 50, 100)
    if codegen == "fast":
        os.environ["XLA_FLAGS"] = f"{os.environ.get('XLA_FLAGS', '')} {FAST_CODEGEN}".strip()
        os.environ[FAST_COMPILE] = "1"
        jax.config.update("jax_disable_most_optimizations", True)
    compile_cache.enable(COMPILE_CACHE)
    # No trace cache (kinetix_cli.trace_cache) for the suite or the processes it starts: measured on fresh clones,
    # each `make test` wrote ~100 new traces (keys that differ from run to run, not yet found) and took 3 min 24 s
    # against 2 min 34 s without it. tests/kinetix_cli/test_trace_cache.py turns it on in folders of its own.
    os.environ[trace_cache.VARIABLE] = "off"
    # The fuzz tests (tests/hostile/test_fuzz.py) draw 300 examples per parser, derandomized; make test (-m "not
    # slow") draws 100 (~20 s less here).
    quick = config.getoption("markexpr", "") == "not slow"
    hypothesis.settings.register_profile("kinetix", max_examples=100 if quick else 300)
    hypothesis.settings.load_profile("kinetix")


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook, which reads the groups
def pytest_collection_modifyitems(config, items):
    """Each module's tests run in one xdist worker, as a group (`make test`: `--dist loadgroup`), unless the module
    names a group of its own: its module-scoped fixtures and the programs its tests trace are then made once, not
    once in each worker that a test of it lands on (three workers each warmed the browser test's studio, ~20 s)."""
    for item in items:
        if item.get_closest_marker("xdist_group") is None:
            item.add_marker(pytest.mark.xdist_group(item.module.__name__))


@pytest.fixture(scope="session")
def tiny_pool():
    """The tiny run's training levels on the device."""
    return level_pool(tiny_config())


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory, tiny_pool):
    """A finished tiny run (6 updates, checkpoints 2, 4 and 6, evaluations at 4 and 6): its run directory, which
    tests only read. Trained once per session: under xdist the first worker to ask trains it into the session's
    folder shared by all workers (under a file lock) and the others read it there (each worker trained its own
    before, ~20 s each here)."""
    if "PYTEST_XDIST_WORKER" not in os.environ:  # one process: nothing to share
        run_dir = tmp_path_factory.mktemp("runs") / "tiny"
        train(tiny_config(), run_dir, pool=tiny_pool)
        return run_dir
    shared = tmp_path_factory.getbasetemp().parent  # this session's, one per `pytest -n` run
    run_dir, done = shared / "tiny-run", shared / "tiny-run.done"
    with FileLock(shared / "tiny-run.lock"):
        if not done.exists():
            shutil.rmtree(run_dir, ignore_errors=True)  # a worker that failed mid-run
            train(tiny_config(), run_dir, pool=tiny_pool)
            done.touch()
    return run_dir


@pytest.fixture(scope="session")
def first_chunk():
    """Chunk 0 of a size-s set generated at seed 3 (`CHUNK` levels sampled, then filtered) by the library: its
    generate config, kept levels and counts. `kinetix generate --seed 3 --chunk 32` starts with the same chunk."""
    config = make_config("s", CHUNK)
    return config, generate_chunk(config, seed=3, index=0)


@pytest.fixture(scope="session")
def sfl_run(tmp_path_factory):
    """The finished tiny SFL run on `LEARN_LEVEL` (300 updates, checkpoints 148, 296, 300): its `TrainResult` and
    run directory."""
    config = sfl_config()
    run_dir = tmp_path_factory.mktemp("runs") / "sfl"
    return train(config, run_dir, pool=level_pool(config)), run_dir
