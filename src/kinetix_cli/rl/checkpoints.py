"""Checkpoints of training runs (orbax): the whole training state every `run.checkpoint_every` updates, and the
policy of a run read back for evaluation, rollouts and fine-tuning.

A run directory holds `config.yaml` (the resolved experiment config) and `checkpoints/<update>/`; a checkpoint
is the whole `Runner` (parameters, optimiser state, environments, PRNG key as raw key data), so a resumed run
continues bit for bit.
"""

from __future__ import annotations

from pathlib import Path

import jax
import numpy as np
import orbax.checkpoint as ocp

from kinetix_cli.config import CONFIG_FILENAME, ExperimentConfig, load_config
from kinetix_cli.errors import UserError
from kinetix_cli.rl.ppo import Runner

CHECKPOINTS = "checkpoints"
KEEP = 3
"""Checkpoints kept per run (the oldest are deleted)."""


def checkpoint_manager(run_dir: Path) -> ocp.CheckpointManager:
    """The orbax manager of `run_dir/checkpoints`."""
    options = ocp.CheckpointManagerOptions(max_to_keep=KEEP)
    return ocp.CheckpointManager(Path(run_dir).resolve() / CHECKPOINTS, options=options)


def save_runner(manager: ocp.CheckpointManager, update: int, runner: Runner) -> None:
    """Write checkpoint `update` and wait until it is on disk (a kill after this loses no finished update)."""
    manager.save(update, args=ocp.args.StandardSave(runner.replace(key=jax.random.key_data(runner.key))))
    manager.wait_until_finished()


def restore_runner(manager: ocp.CheckpointManager, update: int, like: Runner) -> Runner:
    """Checkpoint `update`, with the tree structure, shapes and dtypes of `like` (as host arrays: see
    `load_policy`)."""
    template = like.replace(key=jax.random.key_data(like.key))
    restored = jax.tree.map(np.asarray, manager.restore(update, args=ocp.args.StandardRestore(template)))
    return restored.replace(key=jax.random.wrap_key_data(restored.key))


def load_policy(path: str | Path) -> tuple[ExperimentConfig, object, int]:
    """(config, params, update) from a run directory (latest checkpoint) or one checkpoint folder
    `RUN/checkpoints/<update>`. The parameters come as host numpy arrays, so jitted functions see them exactly as
    freshly initialised ones (device arrays committed by orbax would be a new signature, and a recompile)."""
    path = Path(path)
    run_dir, step = path, None
    if path.parent.name == CHECKPOINTS and path.name.isdigit():
        run_dir, step = path.parent.parent, int(path.name)
    config_file = run_dir / CONFIG_FILENAME
    if not config_file.is_file():
        raise UserError(f"{path}: not a run directory (no {CONFIG_FILENAME}) or a checkpoint folder inside one")
    config = load_config(config_file)
    manager = ocp.CheckpointManager((run_dir / CHECKPOINTS).resolve())
    step = manager.latest_step() if step is None else step
    if step is None or step not in manager.all_steps():
        raise UserError(f"{path}: no checkpoint{'' if step is None else f' {step}'} in {run_dir / CHECKPOINTS}")
    try:
        restored = manager.restore(step, args=ocp.args.StandardRestore())
    except Exception as exc:  # orbax raises many types for damaged files
        raise UserError(
            f"{run_dir / CHECKPOINTS / str(step)}: cannot read the checkpoint ({type(exc).__name__})"
        ) from None
    return config, jax.tree.map(np.asarray, restored["params"]), int(step)
