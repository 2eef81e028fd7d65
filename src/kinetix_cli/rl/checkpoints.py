"""Checkpoints of training runs (orbax): the whole training state every `run.checkpoint_every` updates, and the
policy of a run read back for evaluation, rollouts and fine-tuning.

A run directory holds `config.yaml` (the resolved experiment config) and `checkpoints/<update>/`; a checkpoint
is the whole `Runner` (parameters, optimiser state, environments, PRNG key as raw key data), so a resumed run
continues bit for bit.

Checkpoints prove their bytes: beside orbax's files, `checkpoints/<update>/kinetix-checksums.json`
(`kinetix-checksums/1`) holds the sha256 of every file orbax wrote (array data and metadata), verified before
orbax reads anything; the arrays' names, shapes and dtypes (orbax's metadata) are compared with the run's config
before they are restored. So a damaged or mismatched checkpoint is one `UserError` naming it and the first bad
file or array, and orbax never fails half-way. A checkpoint without a checksum file (runs from before it existed)
is read unverified.
"""

from __future__ import annotations

import contextlib
import hashlib
import logging
import os
import shutil
import traceback
import warnings
from collections.abc import Iterator
from pathlib import Path

import jax
import numpy as np
import orbax.checkpoint as ocp
from flax import serialization

from kinetix_cli.config import CONFIG_FILENAME, ExperimentConfig, load_config
from kinetix_cli.env.level import Level
from kinetix_cli.errors import UserError
from kinetix_cli.io import atomic_write_json, read_format
from kinetix_cli.parallel import is_primary, sync
from kinetix_cli.rl.buffer import LevelBuffer
from kinetix_cli.rl.ppo import Runner
from kinetix_cli.rl.trees import tree_mismatch

CHECKPOINTS = "checkpoints"
KEEP = 3
"""Checkpoints kept per run (the oldest are deleted)."""
CHECKSUMS_FILE = "kinetix-checksums.json"
CHECKSUMS_FORMAT = "kinetix-checksums/1"


def checkpoint_manager(run_dir: Path, read_only: bool = False) -> ocp.CheckpointManager:
    """The orbax manager of `run_dir/checkpoints` (`read_only`: never creates or deletes anything)."""
    options = ocp.CheckpointManagerOptions(max_to_keep=KEEP, create=not read_only)
    return ocp.CheckpointManager(Path(run_dir).resolve() / CHECKPOINTS, options=options)


@contextlib.contextmanager
def writing(manager: ocp.CheckpointManager) -> Iterator[ocp.CheckpointManager]:
    """Use `manager` to write checkpoints, and close it at the end. orbax reports a failed write (a full disk) in
    log records with stack traces from its background threads, then as an exception of `save_runner`, and again
    when the manager closes: the records are silenced and the close after a failure is quiet, so the caller's
    one line is all the user sees. After a failure the partial checkpoint is removed (its space freed).

    orbax's writer threads and asyncio tasks can outlive the failure: a thread logs its error after the block has
    ended, and asyncio reports each abandoned write task or future when it is garbage-collected, at any later
    moment. `_UnfinishedWrites` drops those reports for the rest of the process: the ones that name the unfinished
    checkpoint's folder, and after a failure the ones whose exception was raised in orbax's code (a bare `OSError:
    No space left on device` names no folder); after a failure, so does the warning of each of its coroutines that
    never ran."""
    for name in ("absl", "asyncio"):
        logger = logging.getLogger(name)
        if not any(isinstance(f, _UnfinishedWrites) for f in logger.filters):
            logger.addFilter(_UnfinishedWrites())
    with _orbax_log_level(logging.CRITICAL):
        try:
            yield manager
        except BaseException:
            _UnfinishedWrites.failed = True
            # the failed write's coroutines that never ran warn when collected, at any later moment
            warnings.filterwarnings("ignore", message="coroutine .* was never awaited", category=RuntimeWarning)
            with contextlib.suppress(Exception):
                manager.close()
            remove_partial_checkpoints(Path(manager.directory).parent)
            raise
        manager.close()


class _UnfinishedWrites(logging.Filter):
    """Drops the log records about a checkpoint write that failed: their message or exception names an unfinished
    checkpoint folder (`PARTIAL`), or, once a write of this process has failed (`failed`), their exception was
    raised in orbax's code. The run's one line already says what failed and what is kept."""

    failed = False

    def filter(self, record: logging.LogRecord) -> bool:
        text = record.getMessage()
        error = record.exc_info[1] if record.exc_info else None
        if error is not None:
            text += str(error)
        return PARTIAL not in text and not (self.failed and error is not None and _raised_in_orbax(error))


def _raised_in_orbax(error: BaseException) -> bool:
    frames = traceback.extract_tb(error.__traceback__)
    return any(f"{os.sep}orbax{os.sep}" in frame.filename for frame in frames)


@contextlib.contextmanager
def _orbax_log_level(level: int) -> Iterator[None]:
    """orbax logs through absl's logger: only records of `level` and above pass while the block runs."""
    absl = logging.getLogger("absl")
    before = absl.level
    absl.setLevel(level)
    try:
        yield
    finally:
        absl.setLevel(before)


# A replicated array is written whole by its first replica. orbax's default on the CPU splits it among its replicas,
# which slices every shard with a small compiled program: 50 compiles for the general recipe's state on 2 devices,
# about a second of every new process's first save. The files hold the same arrays either way.
with _orbax_log_level(logging.ERROR):  # orbax warns that the handler replaces its default
    ocp.type_handlers.register_type_handler(
        jax.Array, ocp.type_handlers.ArrayHandler(use_replica_parallel=False), override=True
    )


def file_digests(step_dir: Path) -> dict[str, str]:
    """sha256 of every file under a checkpoint folder but the checksum file, by path relative to it."""
    return {
        str(file.relative_to(step_dir)): hashlib.sha256(file.read_bytes()).hexdigest()
        for file in sorted(step_dir.rglob("*"))
        if file.is_file() and file.name != CHECKSUMS_FILE
    }


def _on_disk(runner: Runner) -> Runner:
    return runner.replace(key=jax.random.key_data(runner.key))


def save_runner(manager: ocp.CheckpointManager, update: int, runner: Runner) -> None:
    """Write checkpoint `update` and its checksums, and wait until both are on disk (a kill after this loses no
    finished update). In a multi-process run every process calls it (each writes its shards; the primary the
    checksums)."""
    manager.save(update, args=ocp.args.StandardSave(_on_disk(runner)))
    manager.wait_until_finished()
    sync(f"saved {update}")  # every process has written its shards
    if not is_primary():
        return
    step_dir = Path(manager.directory) / str(update)
    atomic_write_json(step_dir / CHECKSUMS_FILE, {"update": update, "files": file_digests(step_dir)}, CHECKSUMS_FORMAT)


def remove_partial_checkpoints(run_dir: Path) -> None:
    """Remove what a failed or killed checkpoint write left in `run_dir/checkpoints` (orbax's temporary folders);
    complete checkpoints stay. Only the primary process removes."""
    if not is_primary():
        return
    for partial in (Path(run_dir) / CHECKPOINTS).glob(f"*{PARTIAL}*"):
        shutil.rmtree(partial, ignore_errors=True)


PARTIAL = ".orbax-checkpoint-tmp"
"""What orbax puts in the name of a checkpoint folder it has not finished."""


def verify_checkpoint(step_dir: Path) -> None:
    """Raise a `UserError` unless every file recorded in the checkpoint's checksums is there with its bytes."""
    file = step_dir / CHECKSUMS_FILE
    if not file.exists():
        return
    recorded = read_format(file, CHECKSUMS_FORMAT, UserError).get("files")
    if not isinstance(recorded, dict) or not recorded:
        raise UserError(f"{file}: files: missing; the checksums of this checkpoint are damaged")
    actual = file_digests(step_dir)
    for name, digest in sorted(recorded.items()):
        if name not in actual:
            raise UserError(f"{step_dir}: {name} is missing; the checkpoint is incomplete")
        if actual[name] != digest:
            raise UserError(f"{step_dir}: {name} does not match its checksum; the checkpoint is damaged")


def _check_fits(step_dir: Path, like) -> None:
    """Raise a `UserError` unless the checkpoint's arrays (orbax metadata, no array read) have the names, shapes
    and dtypes of the tree `like`."""
    try:
        metadata = ocp.StandardCheckpointer().metadata(step_dir / "default").item_metadata.tree
    except Exception as exc:  # orbax raises many types for unreadable metadata
        raise UserError(f"{step_dir}: cannot read the checkpoint's metadata ({type(exc).__name__})") from None
    why = tree_mismatch(like, metadata)
    if why is not None:
        raise UserError(f"{step_dir}: written with other model or PPO settings than this run's config ({why})")


def restore_runner(manager: ocp.CheckpointManager, update: int, like: Runner) -> Runner:
    """Checkpoint `update`, verified, with the tree structure, shapes, dtypes and shardings of `like` (the run's
    fresh state: so the restored arrays are placed as a fresh run's are, and the jitted update is not compiled
    again). A checkpoint that is damaged or was written with other settings is a `UserError`."""
    step_dir = Path(manager.directory) / str(update)
    verify_checkpoint(step_dir)
    template = _on_disk(like)
    _check_fits(step_dir, template)
    try:
        restored = manager.restore(update, args=ocp.args.StandardRestore(template))
    except Exception as exc:  # an unverified (old) checkpoint that orbax cannot read
        raise UserError(f"{step_dir}: cannot restore it ({type(exc).__name__})") from None
    return restored.replace(key=jax.random.wrap_key_data(restored.key))


def _latest(path: Path) -> tuple[Path, ExperimentConfig, int | None]:
    """(run directory, its config, the checkpoint named by `path` or None for the latest) of a run directory or
    of one checkpoint folder `RUN/checkpoints/<update>`."""
    run_dir, step = path, None
    if path.parent.name == CHECKPOINTS and path.name.isdigit():
        run_dir, step = path.parent.parent, int(path.name)
    config_file = run_dir / CONFIG_FILENAME
    if not config_file.is_file():
        raise UserError(f"{path}: not a run directory (no {CONFIG_FILENAME}) or a checkpoint folder inside one")
    config = load_config(config_file)
    if not (run_dir / CHECKPOINTS).is_dir():
        raise UserError(f"{path}: no checkpoint in {run_dir / CHECKPOINTS} (the run wrote none yet)")
    return run_dir, config, step


def _restore_raw(path: Path) -> tuple[ExperimentConfig, dict, Path]:
    """(config, the whole checkpoint as nested dicts of host arrays, its folder) of a run or checkpoint folder,
    verified against its checksums."""
    run_dir, config, step = _latest(path)
    with checkpoint_manager(run_dir, read_only=True) as manager:
        step = manager.latest_step() if step is None else step
        if step is None or step not in manager.all_steps():
            raise UserError(f"{path}: no checkpoint{'' if step is None else f' {step}'} in {run_dir / CHECKPOINTS}")
        where = run_dir / CHECKPOINTS / str(step)
        verify_checkpoint(where)
        try:
            raw = jax.tree.map(np.asarray, manager.restore(step, args=ocp.args.StandardRestore(_on_one_device(where))))
        except Exception as exc:  # an unverified (old) checkpoint that orbax cannot read
            raise UserError(f"{where}: cannot read the checkpoint ({type(exc).__name__})") from None
    return config, raw, where


def _on_one_device(step_dir: Path):
    """The abstract tree of a checkpoint (from its metadata) placed on this process's first device: a
    checkpoint written by a run on several devices or processes reads back anywhere."""
    with _orbax_log_level(logging.ERROR):  # orbax warns that the item folder has no checkpoint metadata of its own
        metadata = ocp.StandardCheckpointer().metadata(step_dir.resolve() / "default").item_metadata.tree  # absolute
    device = jax.sharding.SingleDeviceSharding(jax.local_devices()[0])
    return jax.tree.map(lambda m: jax.ShapeDtypeStruct(m.shape, m.dtype, sharding=device), metadata)


def load_buffer(path: str | Path, placeholder: Level) -> tuple[LevelBuffer, int]:
    """(the curriculum's level buffer, update) of a run's latest checkpoint (or of one checkpoint folder), as host
    arrays; `placeholder` is any batch of levels of the run's size (its structure is filled with the saved
    arrays). A run without a curriculum buffer is a `UserError`."""
    config, raw, where = _restore_raw(Path(path))
    if raw.get("buffer") is None:
        raise UserError(f"{where}: holds no level buffer (the run's curriculum.name is {config.curriculum.name!r})")
    template = LevelBuffer(
        levels=placeholder, score=None, solve_rate=None, size=None, last_seen=None, max_return=None, rounds=None
    )
    return serialization.from_state_dict(template, raw["buffer"]), int(where.name)


def read_policy(path: str | Path) -> tuple[ExperimentConfig, object, Path]:
    """(config, params, checkpoint folder) of a run directory (latest checkpoint) or one checkpoint folder
    `RUN/checkpoints/<update>`, verified against the checkpoint's checksums; whether the parameters fit the
    config's model is `agents.load_policy`'s check. The parameters come as host numpy arrays, so jitted functions
    see them exactly as freshly initialised ones (device arrays committed by orbax would be a new signature, and
    a recompile)."""
    config, raw, where = _restore_raw(Path(path))
    return config, raw["params"], where
