"""Evaluate a trained policy: stochastic attempts per level, solve rate per level and per suite.

A level's solve rate is the share of `attempts` first episodes that end with green touching blue (the
reference's protocol: 20 attempts, actions sampled from the policy). The episodes run in the run's own
environment (`make_env_for_level(config.env, ...)`: its frame skip, episode cap and shaping), with each level's
engine constants. Levels are grouped by size and each size is one batched, jitted rollout of the episode runner,
its episodes split over the process's local devices (`kinetix_cli.parallel`; each episode has its own key, so the
results do not depend on the device count).
A policy reading `symbolic-flat` observations only plays levels of its own size (the vector length depends on
it); entity- and pixel-observation policies play every size.
"""

from __future__ import annotations

import dataclasses
import functools
from pathlib import Path

import flax.linen as nn
import jax
import numpy as np

from kinetix_cli.config import ExperimentConfig
from kinetix_cli.constants import EVAL_FORMAT
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.episode import Outcome, run_episode
from kinetix_cli.env.factory import make_env_for_level
from kinetix_cli.env.level import Level, share_engine_params, stack_levels
from kinetix_cli.errors import UserError
from kinetix_cli.io import read_format
from kinetix_cli.levels.files import load_level
from kinetix_cli.levels.suites import shown_path
from kinetix_cli.parallel import make_mesh, pad_batch, replicate, shard_batch, using
from kinetix_cli.rl.networks import MIRROR_MODES, make_network, mirror_policy, sampling_policy
from kinetix_cli.trace_cache import cached_jit


@dataclasses.dataclass
class LevelResult:
    """Evaluation of one level file."""

    level: str
    suite: str
    size: str
    solve_rate: float
    mean_return: float
    mean_length: float


@cached_jit(static_argnames=("env", "network", "horizon", "level_axes", "mirror"))
def play_policy(
    params,
    env_params: EnvParams,
    levels: Level,
    keys: jax.Array,
    *,
    env: KinetixEnv,
    network: nn.Module,
    horizon: int,
    level_axes=0,
    mirror: str | None = None,
) -> Outcome:
    """One episode per (level, key) pair (leading axes equal) with actions sampled from the network, or with
    `mirror` (a `networks.MIRROR_MODES` mode; `env` a `MirrorPairEnv`) from its view of the level joined with its
    view of the mirror image; `level_axes` from `share_engine_params`."""
    policy = sampling_policy(network, params) if mirror is None else mirror_policy(network, params, mirror)
    episode = functools.partial(run_episode, env, env_params, policy=policy, horizon=horizon)
    return jax.vmap(lambda level, key: episode(level, key=key), in_axes=(level_axes, 0))(levels, keys)


class Evaluator:
    """Plays a policy on a fixed list of level files. Built once (files loaded, levels batched per size), then
    called with parameters as often as needed: `kinetix eval` calls it once, training calls it every
    `run.eval_every` updates. The jitted rollout is shared by every evaluator with the same settings. Episodes
    are split over `devices` local devices (None: all). With `mirror` (a `networks.MIRROR_MODES` mode) the policy
    acts on its view of each level joined with its view of the level's mirror image (`networks.mirror_policy`)."""

    def __init__(
        self,
        config: ExperimentConfig,
        files: list[Path],
        attempts: int,
        devices: int | None = None,
        mirror: str | None = None,
    ):
        if mirror is not None and mirror not in MIRROR_MODES:
            raise UserError(f"--mirror: unknown mode {mirror!r}; choose one of {', '.join(MIRROR_MODES)}")
        if mirror is not None and config.model.reads_pairs:
            raise UserError(
                f"--mirror: this policy is already joined with its mirror image (model.mirror={config.model.mirror})"
            )
        self.attempts, self.mirror = attempts, mirror
        self.mesh = make_mesh(devices, local_only=True)
        self.network = make_network(config.model, config.env)
        self.horizon = config.env.max_steps
        by_size: dict[str, list] = {}
        for path in files:
            spec = load_level(path)
            by_size.setdefault(spec.default_size(), []).append((path, spec))
        self._groups = []
        for size, entries in by_size.items():
            pairs = config.model.reads_pairs or mirror is not None
            env, env_params = make_env_for_level(
                config.env, size, str(entries[0][0]), pairs, config.model.reads_attention
            )
            levels = stack_levels([spec.build(env.static) for _, spec in entries])
            repeated = jax.tree.map(lambda x: np.repeat(np.asarray(x), attempts, axis=0), levels)  # host side
            levels, level_axes = share_engine_params(repeated)
            env_params, levels = replicate(env_params, self.mesh), self._split(levels, level_axes)
            self._groups.append((size, [path for path, _ in entries], env, env_params, levels, level_axes))

    def _split(self, levels: Level, level_axes) -> Level:
        """The episodes' levels on the devices: batched parts split (padded to a multiple of the device count),
        engine constants shared by all levels replicated."""
        shard = lambda tree: shard_batch(pad_batch(tree, self.mesh.size), self.mesh)  # noqa: E731
        if level_axes == 0:
            return shard(levels)
        return levels.replace(
            physics=shard(levels.physics),
            bindings=shard(levels.bindings),
            engine_params=replicate(levels.engine_params, self.mesh),
        )

    def __call__(self, params, seed: int = 0) -> list[LevelResult]:
        """`attempts` sampled episodes of every level with the policy `params`; one result per level file."""
        results = []
        params = replicate(params, self.mesh)
        for size, paths, env, env_params, levels, level_axes in self._groups:
            keys = jax.random.key_data(jax.random.split(jax.random.key(seed), len(paths) * self.attempts))
            keys = jax.random.wrap_key_data(shard_batch(pad_batch(keys, self.mesh.size), self.mesh))
            play = functools.partial(
                play_policy,
                env=env,
                network=self.network,
                horizon=self.horizon,
                level_axes=level_axes,
                mirror=self.mirror,
            )
            with using(self.mesh):
                outcome = jax.device_get(play(params, env_params, levels, keys))
            for i, path in enumerate(paths):
                rows = slice(i * self.attempts, (i + 1) * self.attempts)
                results.append(
                    LevelResult(
                        level=shown_path(path),
                        suite=shown_path(Path(path).parent),
                        size=size,
                        solve_rate=float(np.mean(outcome.solved[rows])),
                        mean_return=float(np.mean(outcome.total_return[rows])),
                        mean_length=float(np.mean(outcome.length[rows])),
                    )
                )
        return results


def evaluate(
    config: ExperimentConfig,
    params,
    files: list[Path],
    attempts: int,
    seed: int = 0,
    devices: int | None = None,
    mirror: str | None = None,
) -> list[LevelResult]:
    """Play `attempts` episodes of every level file with the policy; one batched rollout per size, split over
    `devices` local devices (None: all); `mirror` as in `Evaluator`."""
    return Evaluator(config, files, attempts, devices, mirror)(params, seed)


def evaluation_record(
    policy: str, update: int | None, attempts: int, seed: int, results: list[LevelResult], mirror: str | None = None
) -> dict:
    """The payload of an evaluation file (`EVAL_FORMAT`): what was played, each level's result and each suite's
    means. `kinetix eval --json` and training's `RUN/evaluations/<update>.json` write the same record."""
    return {
        "policy": policy,
        "update": update,
        "attempts": attempts,
        "seed": seed,
        "mirror": mirror,
        "levels": [dataclasses.asdict(r) for r in results],
        "suites": suite_summary(results),
    }


def read_evaluation(path: str | Path) -> dict:
    """The record of an evaluation file (`EVAL_FORMAT`: `kinetix eval --json`, or a run's `evaluations/<update>.json`);
    another format or a malformed file is one `UserError` naming the file and the field."""
    record = read_format(path, EVAL_FORMAT, UserError)
    levels, suites = record.get("levels"), record.get("suites")
    if not isinstance(levels, list) or not isinstance(suites, dict):
        raise UserError(f"{path}: levels/suites: missing; give files `kinetix eval --json` wrote")
    number = lambda x: isinstance(x, int | float) and not isinstance(x, bool)  # noqa: E731
    if not all(isinstance(e, dict) and {"level", "suite"} <= e.keys() and number(e.get("solve_rate")) for e in levels):
        raise UserError(f"{path}: levels: every entry needs a level, a suite and a solve_rate")
    if not all(isinstance(suite, dict) and number(suite.get("solve_rate")) for suite in suites.values()):
        raise UserError(f"{path}: suites: every suite needs a solve_rate")
    return record


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
