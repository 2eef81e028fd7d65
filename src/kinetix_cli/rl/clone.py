"""Learning from solved levels: behaviour cloning of the solutions of a solved level set (`kinetix levels solve`).

A cloning step draws `clone.batch` solved levels, replays each with its stored actions in the run's environment
(the observations are replayed, not stored: a set holds levels and actions only) and takes one Adam step on the
mean negative log-likelihood of the stored actions over the steps before each level's solve. `train` runs
`clone.updates` such steps before PPO (behaviour cloning, then PPO), and with `clone.coef` one step of that weight
after every PPO update (PPO with a cloning loss, alternating). The policy's own action masking applies: entries no
actuator of the level uses count in neither.
"""

from __future__ import annotations

import functools
import json
import time
from pathlib import Path

import flax.linen as nn
import jax
import jax.numpy as jnp
import optax
from flax import struct

from kinetix_cli.config import ExperimentConfig
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.factory import make_env_for_level
from kinetix_cli.env.level import Level, index_level, to_device
from kinetix_cli.errors import UserError
from kinetix_cli.io import atomic_write_text
from kinetix_cli.levels.levelset import load_levelset, solved_rows
from kinetix_cli.levels.solution import SOLUTION_SETTINGS
from kinetix_cli.parallel import batch_sharded, replicate
from kinetix_cli.rl.ppo import Runner, make_optimizer

CLONE_METRICS = ("clone_loss", "clone_accuracy")
"""What a cloning step measures: the loss, and the share of steps whose most likely action is the stored one."""


@struct.dataclass
class Demonstrations:
    """The solved levels of a set on the device: `levels` (n, ...), `actions` (n, steps, 6) int32, `length` (n,)
    steps to each solve."""

    levels: Level
    actions: jax.Array
    length: jax.Array


def load_demonstrations(config: ExperimentConfig) -> tuple[Demonstrations, str]:
    """The solved levels of `clone.levels` and the size they were written at; a UserError naming the field if the
    set holds no solutions, none solved, or was solved in an environment the run's does not share."""
    path, env = config.clone.levels, config.env
    for field in ("frame_skip", "action"):
        if getattr(env, field) != getattr(SOLUTION_SETTINGS, field):
            raise UserError(
                f"clone.levels: solutions are played with env.{field} {getattr(SOLUTION_SETTINGS, field)!r}; this "
                f"run has {getattr(env, field)!r}"
            )
    try:
        levelset = load_levelset(path)
    except UserError as exc:
        raise UserError(f"clone.levels: {exc}") from None
    solved = solved_rows(levelset, path, "clone.levels")
    levels = index_level(levelset.levels, solved)
    demos = Demonstrations(
        levels=to_device(levels),
        actions=jnp.asarray(levelset.solutions.actions[solved], jnp.int32),
        length=jnp.asarray(levelset.solutions.length[solved]),
    )
    return demos, levelset.manifest["size"]


def demonstration_env(config: ExperimentConfig, size: str) -> tuple[KinetixEnv, EnvParams]:
    """The run's environment built at the demonstrations' size (the training network's observation must play it)."""
    return make_env_for_level(
        config.env, size, "clone.levels", pairs=config.trains_on_pairs, attention=config.model.reads_attention
    )


def replay_observations(env: KinetixEnv, params: EnvParams, demos: Demonstrations, key: jax.Array, count: int):
    """`count` demonstrations drawn uniformly, replayed: the observations (steps, count, ...), the stored actions
    (steps, count, 6) and which steps come before the solve (steps, count) bool."""
    rows = jax.random.randint(key, (count,), 0, demos.length.shape[0])
    levels = batch_sharded(jax.tree.map(lambda x: x[rows], demos.levels))
    actions = jnp.swapaxes(demos.actions[rows], 0, 1)
    state = jax.vmap(env.initial_state)(levels)

    def step(state, action):
        obs = jax.vmap(env.observe)(state)
        _, state, *_ = jax.vmap(env.step_env, in_axes=(0, 0, None))(state, action, params)
        return state, obs

    _, observations = jax.lax.scan(step, state, actions)
    valid = jnp.arange(actions.shape[0])[:, None] < demos.length[rows][None]
    return observations, actions, valid


def clone_loss(apply_fn, params, observations, actions, valid) -> tuple[jax.Array, dict]:
    """Mean negative log-likelihood of the stored actions over the valid steps, and the metrics."""
    dist, _ = apply_fn(params, observations)
    weight = valid.astype(jnp.float32) / jnp.maximum(valid.sum(), 1)
    loss = -(dist.log_prob(actions) * weight).sum()
    accuracy = (jnp.all(dist.mode() == actions, axis=-1) * weight).sum()
    return loss, {"clone_loss": loss, "clone_accuracy": accuracy}


@functools.partial(jax.jit, static_argnames=("env", "network", "optimizer", "count", "coef"))
def clone_step(
    params,
    opt_state,
    env_params: EnvParams,
    demos: Demonstrations,
    key: jax.Array,
    *,
    env: KinetixEnv,
    network: nn.Module,
    optimizer: optax.GradientTransformation,
    count: int,
    coef: float = 1.0,
):
    """One cloning step of weight `coef` on `count` replayed demonstrations. Returns (params, opt_state, metrics)."""
    observations, actions, valid = replay_observations(env, env_params, demos, key, count)

    def loss(params):
        value, metrics = clone_loss(network.apply, params, observations, actions, valid)
        return coef * value, metrics

    grads, metrics = jax.grad(loss, has_aux=True)(params)
    updates, opt_state = optimizer.update(grads, opt_state, params)
    return optax.apply_updates(params, updates), opt_state, metrics


class Cloning:
    """A training run's behaviour cloning: the demonstrations on the device (replicated over `mesh`), their
    environment, and the steps before and beside PPO."""

    def __init__(self, config: ExperimentConfig, demos: Demonstrations, size: str, mesh, network):
        self.config, self.network = config, network
        self.demos = replicate(demos, mesh)
        env, env_params = demonstration_env(config, size)
        self.env, self.env_params = env, replicate(env_params, mesh)
        self.ppo_optimizer = make_optimizer(config.ppo)  # one object: a static argument of the jitted step

    def _step(self, params, opt_state, key, optimizer, coef: float):
        settings = self.config.clone
        return clone_step(
            params,
            opt_state,
            self.env_params,
            self.demos,
            key,
            env=self.env,
            network=self.network,
            optimizer=optimizer,
            count=settings.batch,
            coef=coef,
        )

    def before_ppo(self, runner: Runner, run_key: jax.Array, log: Path | None, progress) -> Runner:
        """`clone.updates` cloning steps with an Adam of their own from the runner's parameters; PPO then starts
        with a fresh optimiser state. Each step's record goes to `log` (written once, at the end) and `progress`."""
        settings = self.config.clone
        optimizer = optax.chain(
            optax.clip_by_global_norm(self.config.ppo.max_grad_norm), optax.adam(settings.lr, eps=1e-5)
        )
        params, opt_state, records = runner.params, optimizer.init(runner.params), []
        for step in range(settings.updates):
            tic = time.perf_counter()
            key = jax.random.fold_in(jax.random.fold_in(run_key, 3), step)
            params, opt_state, metrics = self._step(params, opt_state, key, optimizer, 1.0)
            metrics = {k: float(v) for k, v in jax.device_get(metrics).items()}
            record = {"clone_step": step + 1, "clone_steps": settings.updates, **metrics}
            records.append(record | {"seconds": time.perf_counter() - tic})
            if progress is not None and log is not None:
                progress(record)
        if log is not None:
            try:
                atomic_write_text(log, "".join(json.dumps(r) + "\n" for r in records))
            except OSError as exc:
                raise UserError(f"{log}: cannot write: {exc.strerror or exc}") from None
        return runner.replace(params=params, opt_state=make_optimizer(self.config.ppo).init(params)).placed()

    def beside_ppo(self, runner: Runner, key: jax.Array) -> tuple[Runner, dict]:
        """One cloning step of weight `clone.coef` on the PPO optimiser, and its metrics (device scalars)."""
        coef = self.config.clone.coef
        params, opt_state, metrics = self._step(runner.params, runner.opt_state, key, self.ppo_optimizer, coef)
        return runner.replace(params=params, opt_state=opt_state).placed(), metrics
