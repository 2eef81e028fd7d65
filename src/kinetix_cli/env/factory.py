"""The one way from settings to an environment: `make_env(config.env)` for training, evaluation, rollouts, the
solver and the generator's filters, so a setting (frame skip, episode cap, shaping, observation, action) means
the same everywhere. A run's saved config rebuilds its environment exactly."""

from __future__ import annotations

from engine import SIZES, Static
from kinetix_cli.config import EnvSettings
from kinetix_cli.constants import SIZE_INDEPENDENT_OBSERVATIONS
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.mirror import MirrorPairEnv
from kinetix_cli.errors import UserError


def make_env(
    settings: EnvSettings, static: Static | None = None, pairs: bool = False, attention: bool = True
) -> tuple[KinetixEnv, EnvParams]:
    """The environment and its parameters for `settings` (an experiment's `env` section).

    Args:
        settings: size, observation, action, frame skip, episode cap and shaping.
        static: capacities to build at instead of `settings.size` (an entity-observation policy plays levels of
            other sizes; see `constants.SIZE_INDEPENDENT_OBSERVATIONS`).
        pairs: observe every state and its mirror image (`mirror.MirrorPairEnv`): what a model with
            `model.mirror` reads (`ModelSettings.reads_pairs`).
        attention: compute the entity observation's attention mask, which only the transformer reads
            (`ModelSettings.reads_attention`); False leaves it all False, at no cost.
    """
    env = (MirrorPairEnv if pairs else KinetixEnv)(
        static=SIZES[settings.size] if static is None else static,
        observation=settings.observation,
        action=settings.action,
        frame_skip=settings.frame_skip,
        attention=attention,
    )
    return env, EnvParams(max_steps=settings.max_steps, dense_reward_scale=settings.dense_reward_scale)


def make_env_for_level(
    settings: EnvSettings, level_size: str, source: str, pairs: bool = False, attention: bool = True
) -> tuple[KinetixEnv, EnvParams]:
    """The environment of `settings` built at a level's size, for a policy trained with `settings` to play it.

    A policy reading a size-independent observation (`constants.SIZE_INDEPENDENT_OBSERVATIONS`) plays levels of
    any size; one reading `symbolic-flat` plays its own size only: another size is a `UserError` naming `source`.
    """
    if settings.observation not in SIZE_INDEPENDENT_OBSERVATIONS and level_size != settings.size:
        raise UserError(
            f"{source}: a size-{level_size} level; this policy reads {settings.observation} observations of size "
            f"{settings.size} only"
        )
    return make_env(settings, SIZES[level_size], pairs, attention)
