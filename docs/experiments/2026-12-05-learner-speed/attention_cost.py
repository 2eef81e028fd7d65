"""Cost of the entity observation's attention mask in the rollout's env step (rel-mlp never reads it).

Run on the source before the change (PYTHONPATH=<checkout of 11c143b>/src), NO_ATTN=1 replacing the mask with
zeros as `KinetixEnv(attention=False)` now does; 256 envs x 32 steps of size s, random actions, restarts drawn from
256 random levels; prints the median of 7 calls. Measured 2026-12-05 06:24, alternating: 385 / 305 / 437 / 306 ms."""
import os, sys, time
import jax, jax.numpy as jnp
from engine import SIZES
import kinetix_cli.env.observations as O
if os.environ.get("NO_ATTN"):
    O.attention_masks = lambda static, physics, mask: jnp.zeros((4, static.num_bodies, static.num_bodies), bool)
from kinetix_cli.bench.env import random_levels
from kinetix_cli.config import EnvSettings
from kinetix_cli.env.factory import make_env
from kinetix_cli.env.level import draw_levels
envs, steps = 256, 32
env, params = make_env(EnvSettings(size="s", observation="symbolic-entity"))
pool = random_levels(SIZES["s"], 256, 0)
state = jax.vmap(lambda l: env.reset_to_level(l)[1])(draw_levels(pool, jax.random.key(0), envs))
step = jax.vmap(env.step, in_axes=(0, 0, None, 0))
n = len(env.action_space.nvec) if hasattr(env.action_space, "nvec") else 6
@jax.jit
def run(state, key):
    def body(carry, _):
        state, key, total = carry
        key, k1, k2 = jax.random.split(key, 3)
        action = jax.random.randint(k1, (envs, 6), 0, 3)
        obs, state, reward, term, trunc, info = step(state, action, params, draw_levels(pool, k2, envs))
        return (state, key, total + reward.sum() + jax.tree.reduce(lambda a, b: a + b, jax.tree.map(lambda x: x.astype(jnp.float32).sum(), (obs, info["final_observation"])))), None
    return jax.lax.scan(body, (state, key, 0.0), None, length=steps)[0]
carry = jax.block_until_ready(run(state, jax.random.key(1)))
ts = []
for i in range(7):
    t = time.perf_counter(); carry = jax.block_until_ready(run(carry[0], carry[1])); ts.append(time.perf_counter() - t)
ts.sort()
print(f"NO_ATTN={os.environ.get('NO_ATTN','')}: median {ts[3]*1e3:.0f} ms per {envs}x{steps} steps = {envs*steps/ts[3]:,.0f} env steps/s")
