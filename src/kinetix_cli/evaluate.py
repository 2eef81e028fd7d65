"""Evaluate a trained policy: stochastic attempts per level, solve rate per level and per suite.

A level's solve rate is the share of `attempts` first episodes that end with green touching blue (the
reference's protocol: 20 attempts, actions sampled from the policy). Levels are grouped by size and each size
is one batched, jitted rollout. A policy reading `symbolic-flat` observations only plays levels of its own size
(the vector length depends on it); entity-observation policies play every size.
"""

from __future__ import annotations

import dataclasses
import functools
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from engine import SIZES
from kinetix_cli.config import ExperimentConfig, load_config
from kinetix_cli.env import EnvConfig, EnvParams, KinetixEnv, reset_to
from kinetix_cli.errors import UserError
from kinetix_cli.level import Level, stack_levels
from kinetix_cli.solve import Outcome

EVAL_FORMAT = "kinetix-eval/1"


def load_policy(path: str | Path) -> tuple[ExperimentConfig, object, int]:
    """(config, params, update) from a run directory (latest checkpoint) or one checkpoint folder
    `RUN/checkpoints/<update>`."""
    import orbax.checkpoint as ocp

    path = Path(path)
    run_dir, step = path, None
    if path.parent.name == "checkpoints" and path.name.isdigit():
        run_dir, step = path.parent.parent, int(path.name)
    config_file = run_dir / "config.yaml"
    if not config_file.is_file():
        raise UserError(f"{path}: not a run directory (no config.yaml) or a checkpoint folder inside one")
    config = load_config(config_file)
    manager = ocp.CheckpointManager((run_dir / "checkpoints").resolve())
    step = manager.latest_step() if step is None else step
    if step is None or step not in manager.all_steps():
        raise UserError(f"{path}: no checkpoint{'' if step is None else f' {step}'} in {run_dir / 'checkpoints'}")
    try:
        restored = manager.restore(step, args=ocp.args.StandardRestore())
    except Exception as exc:  # orbax raises many types for damaged files
        raise UserError(
            f"{run_dir / 'checkpoints' / str(step)}: cannot read the checkpoint ({type(exc).__name__})"
        ) from None
    return config, restored["params"], int(step)


def policy_episode(
    env: KinetixEnv, params_env: EnvParams, horizon: int, apply_fn, params, level: Level, key
) -> Outcome:
    """One episode of at most `horizon` steps from `level` with actions sampled from the policy (no
    auto-reset). Pure; vmap over levels and keys."""
    state = env.state_from_level(level)

    def body(carry, k):
        state, outcome, done = carry
        dist, _ = apply_fn(params, env.observe(state))
        state, reward, ended, info = env.step_env(state, dist.sample(k), params_env)
        return (state, outcome.after_step(done, reward, info), done | ended), None

    keys = jax.random.split(key, horizon)
    (_, outcome, _), _ = jax.lax.scan(body, (state, Outcome.start(state), jnp.bool_(False)), keys)
    return outcome


@dataclasses.dataclass
class LevelResult:
    """Evaluation of one level file."""

    level: str
    suite: str
    size: str
    solve_rate: float
    mean_return: float
    mean_length: float


class Evaluator:
    """Plays a policy on a fixed list of level files. Built once (files loaded, levels batched per size, one
    jitted rollout per size), then called with parameters as often as needed: `kinetix eval` calls it once,
    training calls it every `run.eval_every` updates without recompiling."""

    def __init__(self, config: ExperimentConfig, files: list[Path], attempts: int):
        from kinetix_cli.level_file import load_level
        from kinetix_cli.train import network_for

        self.attempts = attempts
        flat = config.env.observation != "symbolic-entity"
        by_size: dict[str, list] = {}
        for path in files:
            spec = load_level(path)
            size = next(name for name, s in SIZES.items() if s == spec.default_static())
            if flat and size != config.env.size:
                raise UserError(
                    f"{path}: a size-{size} level; this policy reads {config.env.observation} observations of size "
                    f"{config.env.size} only"
                )
            by_size.setdefault(size, []).append((path, spec))
        apply_fn = network_for(config).apply
        env_params = EnvParams(max_steps=config.env.max_steps, dense_reward_scale=config.env.dense_reward_scale)
        self._groups = []
        for size, entries in by_size.items():
            static = SIZES[size]
            levels = stack_levels([spec.build(static) for _, spec in entries])
            env = KinetixEnv(
                EnvConfig(static, observation=config.env.observation, action=config.env.action),
                reset_to(jax.tree.map(lambda x: x[0], levels)),
            )
            repeated = jax.tree.map(lambda x: jnp.repeat(jnp.asarray(x), attempts, axis=0), levels)
            play = jax.jit(functools.partial(_play, env, env_params, config.env.max_steps, apply_fn))
            self._groups.append((size, [path for path, _ in entries], repeated, play))

    def __call__(self, params, seed: int = 0) -> list[LevelResult]:
        """`attempts` sampled episodes of every level with the policy `params`; one result per level file."""
        results = []
        for size, paths, levels, play in self._groups:
            keys = jax.random.split(jax.random.key(seed), len(paths) * self.attempts)
            outcome = jax.device_get(play(params, levels, keys))
            for i, path in enumerate(paths):
                rows = slice(i * self.attempts, (i + 1) * self.attempts)
                results.append(
                    LevelResult(
                        level=str(path),
                        suite=str(Path(path).parent),
                        size=size,
                        solve_rate=float(np.mean(outcome.solved[rows])),
                        mean_return=float(np.mean(outcome.total_return[rows])),
                        mean_length=float(np.mean(outcome.length[rows])),
                    )
                )
        return results


def evaluate(config: ExperimentConfig, params, files: list[Path], attempts: int, seed: int = 0) -> list[LevelResult]:
    """Play `attempts` episodes of every level file with the policy; one batched rollout per size."""
    return Evaluator(config, files, attempts)(params, seed)


def _play(env: KinetixEnv, env_params: EnvParams, horizon: int, apply_fn, params, levels: Level, keys) -> Outcome:
    episode = functools.partial(policy_episode, env, env_params, horizon, apply_fn, params)
    return jax.vmap(episode)(levels, keys)


def suite_summary(results: list[LevelResult]) -> dict[str, dict]:
    """Mean solve rate, return and length per suite (folder), plus 'all'."""
    groups: dict[str, list[LevelResult]] = {}
    for r in results:
        groups.setdefault(r.suite, []).append(r)
    groups["all"] = results
    return {
        name: {
            "levels": len(rs),
            "solve_rate": float(np.mean([r.solve_rate for r in rs])),
            "mean_return": float(np.mean([r.mean_return for r in rs])),
            "mean_length": float(np.mean([r.mean_length for r in rs])),
        }
        for name, rs in groups.items()
    }


def policy_actions(config: ExperimentConfig, params, spec, seed: int = 0) -> np.ndarray:
    """(max_steps, 6) multi-discrete actions the policy takes in one episode of `spec` (sampled, closed loop), for
    replaying open loop (`kinetix rollout --policy RUN_DIR`); the engine is deterministic, so the replay matches."""
    from kinetix_cli.train import network_for

    if config.env.action != "multi-discrete":
        raise UserError(f"--policy: rollouts replay multi-discrete actions; this run uses {config.env.action}")
    static = spec.default_static()
    if config.env.observation != "symbolic-entity" and static != SIZES[config.env.size]:
        raise UserError(f"{spec.path}: not of size {config.env.size}, the only size this policy observes")
    level = jax.tree.map(jnp.asarray, spec.build(static))
    env = KinetixEnv(EnvConfig(static, observation=config.env.observation), reset_to(level))
    env_params = EnvParams(max_steps=config.env.max_steps, dense_reward_scale=config.env.dense_reward_scale)
    apply_fn = network_for(config).apply

    @jax.jit
    def play(params, key):
        def body(state, k):
            dist, _ = apply_fn(params, env.observe(state))
            action = dist.sample(k)
            return env.step_env(state, action, env_params)[0], action

        keys = jax.random.split(key, config.env.max_steps)
        return jax.lax.scan(body, env.state_from_level(level), keys)[1]

    return np.asarray(play(params, jax.random.key(seed)))
