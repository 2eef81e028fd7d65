"""Which levels SFL's buffer would keep in a run that mixes sizes (issue 25, 2026-11-27).

Scores `count` fresh levels drawn like each listed size, in the slots of `size`, as SFL scores them (the policy
plays 2 copies of each for 256 steps; p = solved / ended episodes), then says how many of each kind are among the
32 most learnable (p (1 - p)) of all of them, and how many tie at the top score. Usage:

    .venv/bin/python benchmarks/general-v2c-cpu-2026-11-27/sfl_buffer.py POLICY SIZE COUNT LIKE,LIKE
"""

import dataclasses
import sys

import jax
import jax.numpy as jnp
import numpy as np

from kinetix_cli.env.factory import make_env
from kinetix_cli.generator.fresh import FreshLevels
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.curricula.sfl import episode_counts

policy, size, count, likes = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4].split(",")
loaded = load_policy(policy)
env, env_params = make_env(dataclasses.replace(loaded.config.env, size=size))
score = jax.jit(episode_counts, static_argnames=("env", "network", "steps", "attempts"))
rates = {}
for i, like in enumerate(likes):
    fresh = FreshLevels.for_size(env.static, size, (like,))
    batches = []
    for b in range(count // 128):
        k_levels, k_play = jax.random.split(jax.random.fold_in(jax.random.key(7), 100 * i + b))
        solved, ended = score(
            loaded.params,
            env_params,
            fresh(k_levels, 128),
            k_play,
            env=env,
            network=loaded.network,
            steps=256,
            attempts=2,
        )
        batches.append(np.asarray(solved / jnp.maximum(ended, 1.0)))
    rates[like] = np.concatenate(batches)
every = np.concatenate(list(rates.values()))
kinds = np.concatenate([[like] * len(r) for like, r in rates.items()])
learnability = every * (1 - every)
top = np.argsort(-learnability, kind="stable")[:32]
print(f"{policy} at size {size}; the 32nd best learnability {learnability[top[-1]]:.4f}")
for like, r in rates.items():
    lr = r * (1 - r)
    print(
        f"  like {like}: {len(r)} levels, never solved {np.mean(r == 0):.0%}, always {np.mean(r == 1):.0%}, "
        f"learnable (0 < p < 1) {np.sum(lr > 0)}, at the top score 0.25 {np.sum(lr >= 0.2499)}, "
        f"in the top 32 (ties in listed order) {np.sum(kinds[top] == like)}"
    )
