"""Starting a training run: the checks that can fail on bad input (before anything is written), then the devices,
levels, environment, network, curriculum and the initial or restored training state `rl.train`'s loop starts from.

`check_run` and `start_run` write nothing; `rl.record.Recorder` writes the run's files.
"""

from __future__ import annotations

import dataclasses
import importlib.util
from pathlib import Path

import jax
import jax.numpy as jnp
from jax.sharding import Mesh

from kinetix_cli.config import (
    CONFIG_FILENAME,
    CloneSettings,
    CurriculumSettings,
    ExperimentConfig,
    PPOSettings,
    RunSettings,
    load_config,
)
from kinetix_cli.env.environment import EnvParams
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import Level
from kinetix_cli.errors import UserError
from kinetix_cli.io import check_output_dir
from kinetix_cli.parallel import check_divisible, fitting_devices, make_mesh, primary_decides, replicate, using
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.checkpoints import CHECKPOINTS, checkpoint_manager, restore_runner
from kinetix_cli.rl.clone import Cloning, load_demonstrations
from kinetix_cli.rl.curricula import Curriculum, curriculum_class, make_curriculum
from kinetix_cli.rl.networks import CRITIC, POLICY_HEAD, replace_subtrees, temper, training_network
from kinetix_cli.rl.pool import fresh_source, level_pool
from kinetix_cli.rl.ppo import Runner, init_runner, make_optimizer
from kinetix_cli.rl.trees import tree_mismatch


@dataclasses.dataclass
class Pool:
    """The training levels of each update: one pool for the run, or (with `levels.refresh_every`) a new generated
    pool every `refresh_every` updates, the `round`-th seeded by the round (a resumed run gets its round's).

    Attributes:
        config: the experiment (`level_pool` reads its `levels`, `env.size` and `run.seed`).
        devices: local devices per process, as `train` was given them.
        mesh: the run's mesh (the pool is replicated on it).
        levels: the current pool (None: fresh levels, sampled inside each update).
        round: the current pool's round.
    """

    config: ExperimentConfig
    devices: int | None
    mesh: Mesh
    levels: Level | None
    round: int = 0

    @property
    def refresh_every(self) -> int:
        """Updates per generated pool (0: one pool for the whole run)."""
        return self.config.levels.refresh_every

    def at(self, update: int) -> Level | None:
        """The pool of update `update` (0-based), generated when its round begins."""
        if self.refresh_every and update // self.refresh_every != self.round:
            self.round = update // self.refresh_every
            generated = level_pool(self.config, make_mesh(self.devices, local_only=True), self.round)
            self.levels = replicate(generated, self.mesh)
        return self.levels

    def logged(self) -> dict:
        """What an update's record says of the pool: its round, when pools are refreshed."""
        return {"pool_round": self.round} if self.refresh_every else {}


@dataclasses.dataclass(frozen=True)
class Restart:
    """`run.restart_unsolved_after`: a run from loaded parameters whose first `after` updates solve no training
    episode starts again, at that update, from the loaded features alone (fresh policy head and critic, new
    optimiser state).

    Attributes:
        after: the update (1-based) after which the run decides.
        params: the parameters it starts again from.
        opt_state: their fresh optimiser state.
    """

    after: int
    params: object
    opt_state: object

    def __call__(self, runner: Runner, record: dict, solved: float) -> tuple[Runner, dict]:
        """The runner and record after update `record["update"]`: restarted (the record says so) when that is the
        deciding update and `solved` (training episodes solved so far) is 0, as the primary process sees it."""
        if record["update"] != self.after or not primary_decides("restart", solved == 0):
            return runner, record
        return runner.replace(params=self.params, opt_state=self.opt_state), record | {"restarted": 1.0}


@dataclasses.dataclass(frozen=True)
class Start:
    """A training run ready for its first update (or the update after the checkpoint it resumes from).

    Attributes:
        mesh: the run's 1-D device mesh (`kinetix_cli.parallel`).
        env_params: the environment's parameters, replicated.
        curriculum: which levels each update trains on, and what runs before it.
        pool: the training levels of each update.
        cloning: behaviour cloning of solved levels (the `clone` section), or None.
        key: the run's key; each update's streams are folded from it and the update.
        runner: the initial or restored training state.
        first_update: 0, or the update of the checkpoint the run resumes from.
        restart: the fallback of `run.restart_unsolved_after`, or None.
        clone_settings: the run's `clone` section.
    """

    mesh: Mesh
    env_params: EnvParams
    curriculum: Curriculum
    pool: Pool
    cloning: Cloning | None
    key: jax.Array
    runner: Runner
    first_update: int
    restart: Restart | None
    clone_settings: CloneSettings

    def clones_first(self) -> bool:
        """Whether behaviour cloning runs before the first PPO update (a resumed run has done it)."""
        return self.cloning is not None and bool(self.clone_settings.updates) and self.first_update == 0

    def clone_beside_ppo(self, runner: Runner, metrics: dict, update: int) -> tuple[Runner, dict]:
        """A cloning step after PPO update `update` (`clone.coef`), its metrics added; else unchanged."""
        if self.cloning is None or not self.clone_settings.coef:
            return runner, metrics
        runner, cloned = self.cloning.beside_ppo(runner, cloning_key(self.key, update))
        return runner, metrics | cloned


def check_run(config: ExperimentConfig, run_dir: str | Path, resume: bool) -> Path:
    """The run's folder, after the checks of the command line: wandb installed if asked for, a new run's folder
    empty, a resumed run's config the one given (only `run.minutes` may change)."""
    run_dir = check_output_dir(run_dir, "--run-dir")
    if config.run.wandb != "off" and importlib.util.find_spec("wandb") is None:
        raise UserError(
            f"run.wandb={config.run.wandb}: wandb is not installed; install it with pip install 'kinetix[wandb]' "
            "or leave run.wandb off (metrics.jsonl is written either way)"
        )
    if not resume and run_dir.exists() and any(run_dir.iterdir()):
        raise UserError(f"--run-dir {run_dir}: not empty; pass --resume to continue it or choose a new folder")
    saved = run_dir / CONFIG_FILENAME
    if resume and saved.exists() and not same_experiment(load_config(saved), config):
        raise UserError(
            f"--resume: {saved} differs from the config given; resume with the run's own config (only "
            "run.minutes may change)"
        )
    return run_dir


def start_run(
    config: ExperimentConfig,
    run_dir: Path,
    resume: bool,
    pool: Level | None,
    init_params,
    devices: int | None,
) -> Start:
    """The run of `config` ready to train (`rl.train.train` has the arguments' meaning). Everything that can fail
    on bad input happens here, before anything is written: a failed start leaves no debris."""
    sizes = split_sizes(config.ppo, config.clone, config.curriculum)
    devices = devices or fitting_devices(sizes)
    mesh = make_mesh(devices)
    for what, size in sizes.items():  # one clear line unless every batch splits evenly
        check_divisible(size, mesh, what)
    demos = load_demonstrations(config) if config.clone.active else None
    if pool is None:  # each process generates a pool on its own devices: the same levels in every process
        pool = level_pool(config, make_mesh(devices, local_only=True))
    with using(mesh):
        fresh = fresh_source(config)
        env, env_params = make_env(config.env, pairs=config.trains_on_pairs, attention=config.model.reads_attention)
        network = training_network(config)
        ppo = config.ppo
        curriculum = make_curriculum(config.curriculum, env=env, network=network, ppo=ppo, fresh=fresh)
        key = replicate(jax.random.key(config.run.seed), mesh)
        levels = None if pool is None else replicate(pool, mesh)
        runner = init_runner(env, network, ppo, levels, key, fresh=fresh, buffer_size=curriculum.buffer_size)
        runner, restart = _loaded(runner, config.run, ppo, init_params, mesh)
        first_update = 0
        if resume and (run_dir / CHECKPOINTS).is_dir():
            with checkpoint_manager(run_dir, read_only=True) as reader:
                if reader.latest_step() is not None:
                    first_update = int(reader.latest_step())
                    runner = restore_runner(reader, first_update, runner)
        cloning = None if demos is None else Cloning(config, *demos, mesh, network)
    return Start(
        mesh=mesh,
        env_params=replicate(env_params, mesh),
        curriculum=curriculum,
        pool=Pool(config, devices, mesh, levels),
        cloning=cloning,
        key=key,
        runner=runner,
        first_update=first_update,
        restart=restart,
        clone_settings=config.clone,
    )


def _loaded(runner: Runner, run: RunSettings, ppo: PPOSettings, params, mesh: Mesh) -> tuple[Runner, Restart | None]:
    """The runner with the parameters the run starts from (`params` given by `--from`, else those `run.init_from`
    names, else its own fresh ones), and the fallback of `run.restart_unsolved_after` (None without)."""
    origin = f"--from {run.init_from}" if params is not None else f"run.init_from {run.init_from}"
    if params is None and run.init_from:
        params = load_policy(run.init_from).params
    if params is None:
        return runner, None
    params = replicate(params, mesh)
    restart = None
    if run.restart_unsolved_after:  # what the run starts again from if its first updates solve nothing: the features
        alone = dataclasses.replace(run, fresh_policy_head=True, fresh_critic=True, policy_temperature=1.0)
        fallback = with_params(runner, params, ppo, origin, alone)
        restart = Restart(run.restart_unsolved_after, fallback.params, fallback.opt_state)
    return with_params(runner, params, ppo, origin, run), restart


def with_params(runner: Runner, params, settings: PPOSettings, origin: str, run: RunSettings) -> Runner:
    """The runner with `params` (from a checkpoint) and a fresh optimiser state; the network must match (else an
    error naming `origin`, the flag or key and where the parameters came from). With `run.fresh_policy_head` the
    actor's output layer keeps the runner's own fresh initialisation; `run.policy_temperature` scales it by
    1 / temperature (logits divided by it); with `run.fresh_critic` the critic keeps the runner's own."""
    why = tree_mismatch(runner.params, params)
    if why is not None:
        raise UserError(f"{origin}: the checkpoint's network does not match this run's model settings ({why})")
    params = jax.tree.map(jnp.asarray, params)
    if run.fresh_policy_head:
        params = replace_subtrees(params, runner.params, POLICY_HEAD)
    if run.policy_temperature != 1.0:
        params = temper(params, run.policy_temperature)
    if run.fresh_critic:
        for name in CRITIC:
            params = replace_subtrees(params, runner.params, name)
    return runner.replace(params=params, opt_state=make_optimizer(settings).init(params))


def same_experiment(saved: ExperimentConfig, given: ExperimentConfig) -> bool:
    """Whether `given` continues the run of `saved`: equal but for the wall-clock budget, which a resumed run may
    extend (the run then trains until its total training time passes the new one)."""
    budget = dataclasses.replace(given.run, minutes=saved.run.minutes)
    return saved == dataclasses.replace(given, run=budget)


def split_sizes(ppo: PPOSettings, clone: CloneSettings, curriculum: CurriculumSettings) -> dict[str, int]:
    """The global size of every batch the run splits across devices, by the setting that sets it."""
    sizes = {"ppo.num_envs": ppo.num_envs} | curriculum_class(curriculum).split_sizes(curriculum)
    return sizes | ({"clone.batch": clone.batch} if clone.active else {})


def scoring_key(run_key: jax.Array, update: int) -> jax.Array:
    """The key of the curriculum's work before `update`: a stream of its own, a function of the update only,
    so a resumed run scores exactly as an uninterrupted one."""
    return jax.random.fold_in(jax.random.fold_in(run_key, 1), update)


def cloning_key(run_key: jax.Array, update: int) -> jax.Array:
    """The key of the cloning step after `update`: a stream of its own, a function of the update only."""
    return jax.random.fold_in(jax.random.fold_in(run_key, 2), update)
