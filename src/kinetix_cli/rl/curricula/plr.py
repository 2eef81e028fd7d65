"""Robust PLR, prioritised level replay (Jiang et al., 2021), as the Kinetix paper runs it: the update itself is
`plr_update`, after the buffer's replay distribution, the level scores and the buffer updates. ACCEL (`accel.py`)
is this update with a mutation round.

Every update resets all environments. With probability `replay_prob` (once the buffer is `min_fill` full) they
replay levels sampled from the buffer, train on them and rescore them; otherwise they play new levels from the
source, which are scored but not trained on (the "robust" variant: gradients only from curated levels), and the
best-scoring of buffer and new levels stay. A level's replay probability mixes its score rank and its staleness:
P = (1 - staleness) P_rank + staleness P_stale, with P_rank proportional to rank^(-1/temperature) and P_stale to the
updates since it was last played.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable

import flax.linen as nn
import jax
import jax.numpy as jnp

from kinetix_cli.config import CurriculumSettings, PPOSettings
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.level import Level, draw_levels, index_level
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.parallel import batch_sharded
from kinetix_cli.rl.buffer import LevelBuffer, top_levels
from kinetix_cli.rl.curricula.base import Curriculum
from kinetix_cli.rl.ppo import LOSS_METRICS, Runner, collect, gae, learn, rollout_metrics
from kinetix_cli.trace_cache import cached_jit


def replay_probabilities(buffer: LevelBuffer, update: jax.Array, curriculum: CurriculumSettings) -> jax.Array:
    """(capacity,) float32 probability of replaying each slot (0 for empty slots; sums to 1 when any is filled)."""
    capacity = buffer.score.shape[0]
    filled = jnp.arange(capacity) < buffer.size
    order = jnp.argsort(jnp.where(filled, -buffer.score, jnp.inf))  # best first, empty slots last
    rank = jnp.zeros(capacity, jnp.float32).at[order].set(jnp.arange(1, capacity + 1, dtype=jnp.float32))
    by_rank = jnp.where(filled, rank ** (-1.0 / curriculum.temperature), 0.0)
    stale = jnp.where(filled, (update - buffer.last_seen).astype(jnp.float32), 0.0)
    by_rank = by_rank / jnp.maximum(by_rank.sum(), 1e-30)
    stale = stale / jnp.maximum(stale.sum(), 1e-30)
    mixed = (1.0 - curriculum.staleness) * by_rank + curriculum.staleness * stale
    return mixed / jnp.maximum(mixed.sum(), 1e-30)


def sample_replay(
    buffer: LevelBuffer, key: jax.Array, count: int, update: jax.Array, curriculum: CurriculumSettings
) -> jax.Array:
    """(count,) int32 buffer slots to replay, drawn with replacement from `replay_probabilities`."""
    probabilities = replay_probabilities(buffer, update, curriculum)
    return jax.random.choice(key, probabilities.shape[0], (count,), p=probabilities)


def level_scores(
    value: jax.Array,
    advantages: jax.Array,
    finished_return: jax.Array,
    done: jax.Array,
    solved: jax.Array,
    best_before: jax.Array,
    curriculum: CurriculumSettings,
) -> tuple[jax.Array, jax.Array, jax.Array]:
    """(score, solve rate, best return), each (num_envs,), of the level each environment played for the whole
    rollout. Inputs are (num_steps, num_envs): value estimates, GAE advantages, returns of episodes that ended
    (0 elsewhere), done and solved flags; `best_before` is the best return known before (-inf for a new level).

    MaxMC: mean over steps of (best return - value); PVL: mean over steps of max(advantage, 0)."""
    ended = done.sum(0)
    best = jnp.maximum(best_before, jnp.where(done > 0, finished_return, -jnp.inf).max(0))
    best = jnp.where(jnp.isfinite(best), best, value.max(0))  # no episode ended: nothing better than the values
    maxmc = (best[None] - value).mean(0)
    pvl = jnp.maximum(advantages, 0.0).mean(0)
    score = maxmc if curriculum.plr_score == "maxmc" else pvl
    return score, solved.sum(0) / jnp.maximum(ended, 1.0), best


def rescore(
    buffer: LevelBuffer, slots: jax.Array, score: jax.Array, solve_rate: jax.Array, best: jax.Array, update
) -> LevelBuffer:
    """The buffer with the replayed `slots` given their new score, solve rate and best return, seen at `update`."""
    return buffer.replace(
        score=buffer.score.at[slots].set(score),
        solve_rate=buffer.solve_rate.at[slots].set(solve_rate),
        max_return=buffer.max_return.at[slots].set(best),
        last_seen=buffer.last_seen.at[slots].set(jnp.asarray(update, jnp.int32)),
    )


def insert(
    buffer: LevelBuffer, levels: Level, score: jax.Array, solve_rate: jax.Array, best: jax.Array, update
) -> LevelBuffer:
    """The buffer after new `levels` were scored: the best-scoring of its levels and the new ones, best first
    (new levels fill empty slots first, then replace lower scores); one more scoring round."""
    capacity = buffer.score.shape[0]
    filled = jnp.arange(capacity) < buffer.size
    join = lambda a, b: jnp.concatenate([a, b])  # noqa: E731
    return top_levels(
        jax.tree.map(join, buffer.levels, levels),
        join(jnp.where(filled, buffer.score, -jnp.inf), score),
        join(buffer.solve_rate, solve_rate),
        capacity,
        join(buffer.last_seen, jnp.full(score.shape, update, jnp.int32)),
        join(buffer.max_return, best),
        buffer.rounds + 1,
    )


Mutation = Callable[[jax.Array, Level, KinetixEnv, CurriculumSettings], Level]
"""mutation(key, levels, env, curriculum) -> the batch of levels, each edited (ACCEL's `accel.mutate_levels`)."""


ROUNDS = ("replay", "mutate", "new")
"""What an update of PLR or ACCEL does: replay buffer levels and train on them, or score candidates without
training, mutations of buffer levels (ACCEL) or new levels from the source."""


def round_keys(runner: Runner) -> tuple[jax.Array, ...]:
    """The update's keys (the runner's next key, then those of its round, new levels, replay slots and mutations),
    shared by `plr_round` and `plr_update`."""
    return tuple(jax.random.split(runner.key, 5))


@functools.partial(jax.jit, static_argnames=("curriculum", "accel"))
def plr_round(runner: Runner, *, curriculum: CurriculumSettings, accel: bool) -> jax.Array:
    """() int32 index in `ROUNDS` of the next update's round. PLR replays with probability `replay_prob` once the
    buffer is `min_fill` full; ACCEL, which follows each replay with a mutation round, picks replay, mutation and
    new levels with probabilities p, p and 1 - p over 1 + p. Otherwise new levels."""
    _, k_round, *_ = round_keys(runner)
    buffer = runner.buffer
    ready = buffer.size >= jnp.maximum(1, round(curriculum.min_fill * buffer.score.shape[0]))
    u, p = jax.random.uniform(k_round), curriculum.replay_prob
    replay = ready & (u < (p / (1.0 + p) if accel else p))
    mutate = ready & ~replay & (u < 2.0 * p / (1.0 + p)) if accel else jnp.zeros((), bool)
    return jnp.where(replay, 0, jnp.where(mutate, 1, 2)).astype(jnp.int32)


@cached_jit(static_argnames=("env", "network", "settings", "fresh", "curriculum", "mutation", "kind"))
def plr_update(
    runner: Runner,
    env_params: EnvParams,
    levels: Level | None,
    *,
    env: KinetixEnv,
    network: nn.Module,
    settings: PPOSettings,
    fresh: FreshLevels | None,
    curriculum: CurriculumSettings,
    mutation: Mutation | None = None,
    kind: str,
) -> tuple[Runner, dict]:
    """One update of robust PLR or, with a `mutation`, ACCEL, of the round `kind` (`ROUNDS`, as `plr_round`
    chose it): every environment is reset to a level of its own and replays it whenever an episode ends. A replay
    round plays buffer levels sampled by `replay_probabilities`, trains on them as `rl.ppo.ppo_update` does and
    rescores them; the other rounds play candidates without training (new levels from the source, `fresh` or
    draws from `levels`; mutations of buffer levels), and the buffer keeps the best-scoring of its levels and
    these.

    The round is chosen on the host, one compiled program per round: a `lax.cond` between them would hold the
    gradient's all-reduce and the levels' gathers, which can stall a CPU split into devices
    (`parallel.per_device`). Metrics: those of `ppo_update` (losses 0 when nothing was trained: `logged` drops
    them), `replay` and `mutate` (1 or 0)."""
    n = settings.num_envs
    buffer = runner.buffer
    key, _, k_new, k_replay, k_mutate = round_keys(runner)
    slots = sample_replay(buffer, k_replay, n, runner.update, curriculum)
    if kind == "replay":
        played = index_level(buffer.levels, slots)
    elif kind == "mutate":
        played = mutation(k_mutate, index_level(buffer.levels, slots), env, curriculum)
    else:
        played = fresh(k_new, n) if fresh is not None else draw_levels(levels, k_new, n)
    played = batch_sharded(played)
    obs, env_state = jax.vmap(env.reset_to_level)(played)
    runner = runner.replace(key=key, obs=obs, env_state=env_state, episode_return=jnp.zeros(n, jnp.float32))
    # --- collect: every environment stays on its level
    runner, transitions, finished_return = collect(
        runner, env_params, lambda _: played, env=env, network=network, num_steps=settings.num_steps
    )
    # --- GAE and the levels' scores
    advantages, targets = gae(transitions, settings.gamma, settings.gae_lambda)
    best_before = buffer.max_return[slots] if kind == "replay" else jnp.full(n, -jnp.inf)
    score, solve_rate, best = level_scores(
        transitions.value, advantages, finished_return, transitions.done, transitions.solved, best_before, curriculum
    )
    # --- train on replayed levels only
    train = lambda r: learn(r, transitions, advantages, targets, network=network, settings=settings)  # noqa: E731
    if kind == "replay":
        runner, losses = train(runner)
        buffer = rescore(buffer, slots, score, solve_rate, best, runner.update)
    else:
        losses = jax.tree.map(lambda x: jnp.zeros(x.shape, x.dtype), jax.eval_shape(train, runner)[1])
        buffer = insert(buffer, played, score, solve_rate, best, runner.update)
    runner = runner.replace(buffer=buffer, update=runner.update + 1).placed()
    modes = {"replay": jnp.float32(kind == "replay"), "mutate": jnp.float32(kind == "mutate")}
    return runner, rollout_metrics(transitions, finished_return, losses) | modes


@dataclasses.dataclass(frozen=True)
class PLR(Curriculum):
    """Robust PLR: a buffer of `curriculum.buffer_size` levels; its scoring rounds are updates that trained
    nothing (their steps are part of the updates' steps)."""

    mutation = None
    """ACCEL's mutation of buffer levels (`accel.ACCEL`), none for PLR."""

    @property
    def buffer_size(self) -> int:
        return self.curriculum.buffer_size

    def update(self, runner, env_params, pool):
        accel = self.mutation is not None
        kind = ROUNDS[int(plr_round(runner, curriculum=self.curriculum, accel=accel))]  # one sync per update
        parts = {"env": self.env, "network": self.network, "settings": self.settings, "fresh": self.fresh}
        return plr_update(
            runner, env_params, pool, **parts, curriculum=self.curriculum, mutation=self.mutation, kind=kind
        )

    def logged(self, metrics: dict) -> dict:
        """A round that trained nothing (new levels or mutations) carries no losses, entropy or KL, so their
        curves show only the updates that learned."""
        if metrics["replay"]:
            return metrics
        return {k: v for k, v in metrics.items() if k not in LOSS_METRICS}

    def scoring_steps(self, runner):
        return int(runner.buffer.rounds) * self.settings.batch_size, False
