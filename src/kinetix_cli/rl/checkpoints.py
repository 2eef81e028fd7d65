"""Checkpoints of training runs (orbax): the whole training state every `run.checkpoint_every` updates, and the
policy of a run read back for evaluation, rollouts and fine-tuning.

A run directory holds `config.yaml` (the resolved experiment config) and `checkpoints/<update>/`; a checkpoint
is the whole `Runner` (parameters, optimiser state, environments, PRNG key as raw key data), so a resumed run
continues bit for bit.

Checkpoints prove their bytes: beside orbax's files, `checkpoints/<update>/kinetix-checksums.json`
(`kinetix-checksums/1`) holds the sha256 of every array's data, verified whenever a checkpoint is read; a
checkpoint without that file (runs from before it existed) is read unverified. Any checkpoint that cannot be read,
does not match its checksums, or does not fit the run's config is one `UserError` naming it.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import jax
import numpy as np
import orbax.checkpoint as ocp

from kinetix_cli.config import CONFIG_FILENAME, ExperimentConfig, load_config
from kinetix_cli.errors import UserError
from kinetix_cli.io import atomic_write_json, read_format
from kinetix_cli.rl.networks import params_fit
from kinetix_cli.rl.ppo import Runner

CHECKPOINTS = "checkpoints"
KEEP = 3
"""Checkpoints kept per run (the oldest are deleted)."""
CHECKSUMS_FILE = "kinetix-checksums.json"
CHECKSUMS_FORMAT = "kinetix-checksums/1"


def checkpoint_manager(run_dir: Path, read_only: bool = False) -> ocp.CheckpointManager:
    """The orbax manager of `run_dir/checkpoints` (`read_only`: never creates or deletes anything)."""
    options = ocp.CheckpointManagerOptions(max_to_keep=KEEP, create=not read_only, read_only=read_only)
    return ocp.CheckpointManager(Path(run_dir).resolve() / CHECKPOINTS, options=options)


def leaf_digests(tree) -> dict[str, str]:
    """sha256 of every array leaf's bytes, keyed by its path ("params/params/Dense_0/kernel")."""
    digests = {}
    for path, leaf in jax.tree_util.tree_flatten_with_path(tree)[0]:
        name = "/".join(str(getattr(k, "name", getattr(k, "key", getattr(k, "idx", k)))) for k in path)
        array = np.ascontiguousarray(np.asarray(leaf))
        digests[name] = hashlib.sha256(
            array.dtype.str.encode() + str(array.shape).encode() + array.tobytes()
        ).hexdigest()
    return digests


def _on_disk(runner: Runner) -> Runner:
    return runner.replace(key=jax.random.key_data(runner.key))


def save_runner(manager: ocp.CheckpointManager, update: int, runner: Runner) -> None:
    """Write checkpoint `update` and its checksums, and wait until both are on disk (a kill after this loses no
    finished update)."""
    runner = _on_disk(runner)
    manager.save(update, args=ocp.args.StandardSave(runner))
    manager.wait_until_finished()
    checksums = Path(manager.directory) / str(update) / CHECKSUMS_FILE
    atomic_write_json(checksums, {"update": update, "leaves": leaf_digests(jax.device_get(runner))}, CHECKSUMS_FORMAT)


def _verify(where: Path, restored, prefix: str = "") -> None:
    """Raise unless every restored leaf under `prefix` matches the checksum recorded for it."""
    file = where / CHECKSUMS_FILE
    if not file.exists():
        return
    recorded = read_format(file, CHECKSUMS_FORMAT).get("leaves")
    if not isinstance(recorded, dict):
        raise UserError(f"{file}: leaves: missing; the checksums of this checkpoint are damaged")
    actual = leaf_digests(restored)
    wanted = {k: v for k, v in recorded.items() if k.startswith(prefix)}
    damaged = sorted(k for k, v in wanted.items() if actual.get(k) != v)
    if damaged:
        raise UserError(f"{where}: array data does not match its checksums ({damaged[0]}); the checkpoint is damaged")


def restore_runner(manager: ocp.CheckpointManager, update: int, like: Runner) -> Runner:
    """Checkpoint `update`, verified, with the tree structure, shapes and dtypes of `like` (as host arrays: see
    `load_policy`). A checkpoint that is damaged or was written with other settings is a `UserError`."""
    where = Path(manager.directory) / str(update)
    try:
        restored = manager.restore(update, args=ocp.args.StandardRestore(_on_disk(like)))
    except Exception as exc:  # orbax raises many types for damaged or mismatched checkpoints
        raise UserError(
            f"{where}: cannot restore it with this run's config (damaged, or written with other model or PPO "
            f"settings: {type(exc).__name__})"
        ) from None
    restored = jax.tree.map(np.asarray, restored)
    _verify(where, restored)
    return restored.replace(key=jax.random.wrap_key_data(restored.key))


def load_policy(path: str | Path) -> tuple[ExperimentConfig, object, int]:
    """(config, params, update) from a run directory (latest checkpoint) or one checkpoint folder
    `RUN/checkpoints/<update>`, verified against the checkpoint's checksums. The parameters come as host numpy
    arrays, so jitted functions see them exactly as freshly initialised ones (device arrays committed by orbax
    would be a new signature, and a recompile)."""
    path = Path(path)
    run_dir, step = path, None
    if path.parent.name == CHECKPOINTS and path.name.isdigit():
        run_dir, step = path.parent.parent, int(path.name)
    config_file = run_dir / CONFIG_FILENAME
    if not config_file.is_file():
        raise UserError(f"{path}: not a run directory (no {CONFIG_FILENAME}) or a checkpoint folder inside one")
    config = load_config(config_file)
    if not (run_dir / CHECKPOINTS).is_dir():
        raise UserError(f"{path}: no checkpoint in {run_dir / CHECKPOINTS} (the run wrote none yet)")
    manager = checkpoint_manager(run_dir, read_only=True)
    step = manager.latest_step() if step is None else step
    if step is None or step not in manager.all_steps():
        raise UserError(f"{path}: no checkpoint{'' if step is None else f' {step}'} in {run_dir / CHECKPOINTS}")
    where = run_dir / CHECKPOINTS / str(step)
    try:
        restored = manager.restore(step, args=ocp.args.StandardRestore())
        params = jax.tree.map(np.asarray, restored["params"])
    except Exception as exc:  # orbax raises many types for damaged files
        raise UserError(f"{where}: cannot read the checkpoint ({type(exc).__name__})") from None
    _verify(where, {"params": params}, prefix="params/")
    if not params_fit(config, params):
        raise UserError(f"{where}: its parameters do not fit the model in {config_file} (another model's checkpoint?)")
    return config, params, int(step)
