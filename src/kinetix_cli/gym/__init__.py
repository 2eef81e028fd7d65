"""Kinetix for other people's training code: a gymnax environment (`make`) for JAX training loops, and Gymnasium
environments (`gymnasium.make_vec("kinetix/Kinetix-v0", num_envs=...)`, `gymnasium.make(...)`) for PyTorch ones.

Importing this package registers `kinetix/Kinetix-v0` with Gymnasium. See docs/gym.md.
"""

from __future__ import annotations

import gymnasium

from kinetix_cli.gym.environment import FRESH, FRESH_LEVELS, GymnaxParams, KinetixGymnax, MultiDiscrete, make
from kinetix_cli.gym.vector import ENV_ID, KinetixGymnasiumEnv, KinetixVectorEnv

__all__ = [
    "ENV_ID",
    "FRESH",
    "FRESH_LEVELS",
    "GymnaxParams",
    "KinetixGymnasiumEnv",
    "KinetixGymnax",
    "KinetixVectorEnv",
    "MultiDiscrete",
    "make",
]

if ENV_ID not in gymnasium.registry:
    gymnasium.register(
        ENV_ID,
        entry_point="kinetix_cli.gym.vector:KinetixGymnasiumEnv",
        vector_entry_point="kinetix_cli.gym.vector:KinetixVectorEnv",
    )
