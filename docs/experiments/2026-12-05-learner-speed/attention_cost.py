"""Cost of the entity observation's attention mask in the rollout's env step (rel-mlp never reads it).

Run on the source before the change (PYTHONPATH=<checkout of 11c143b>/src), NO_ATTN=1 replacing the mask with
zeros as `KinetixEnv(attention=False)` now does; 256 envs x 32 steps of size s, random actions, restarts drawn from
256 random levels; prints the median of 7 calls. Measured 2026-12-05 06:24, alternating: 385 / 305 / 437 / 306 ms."""

import os
import time

import jax
import jax.numpy as jnp

import kinetix_cli.env.observations as observations
from engine import SIZES
from kinetix_cli.bench.env import random_levels
from kinetix_cli.config import EnvSettings
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import draw_levels

if os.environ.get("NO_ATTN"):
    observations.attention_masks = lambda static, physics, mask: jnp.zeros(
        (4, static.num_bodies, static.num_bodies), bool
    )

ENVS, STEPS = 256, 32
env, params = make_env(EnvSettings(size="s", observation="symbolic-entity"))
pool = random_levels(SIZES["s"], 256, 0)
state = jax.vmap(lambda level: env.reset_to_level(level)[1])(draw_levels(pool, jax.random.key(0), ENVS))
step = jax.vmap(env.step, in_axes=(0, 0, None, 0))


def total(tree) -> jax.Array:
    return sum(x.astype(jnp.float32).sum() for x in jax.tree.leaves(tree))


@jax.jit
def run(state, key):
    def body(carry, _):
        state, key, checksum = carry
        key, k_action, k_level = jax.random.split(key, 3)
        action = jax.random.randint(k_action, (ENVS, 6), 0, 3)
        obs, state, reward, *_, info = step(state, action, params, draw_levels(pool, k_level, ENVS))
        return (state, key, checksum + reward.sum() + total((obs, info["final_observation"]))), None

    return jax.lax.scan(body, (state, key, 0.0), None, length=STEPS)[0]


carry = jax.block_until_ready(run(state, jax.random.key(1)))
times = []
for _ in range(7):
    start = time.perf_counter()
    carry = jax.block_until_ready(run(carry[0], carry[1]))
    times.append(time.perf_counter() - start)
median = sorted(times)[3]
print(
    f"NO_ATTN={os.environ.get('NO_ATTN', '')}: median {median * 1e3:.0f} ms = {ENVS * STEPS / median:,.0f} env steps/s"
)
