"""The gymnax path of `kinetix bench gym` on fresh levels, for a tree whose bench stops on them: 64 environments,
a jitted scan of 32 vmapped `env.step` calls with random actions; make, first reset and scan compile timed apart.

    python fresh_gymnax.py s out.json   # PYTHONPATH=<tree>/src to measure another tree
"""

import json
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp

from kinetix_cli.bench.timing import time_keyed
from kinetix_cli.gym import make
from kinetix_cli.provenance import environment_info

size, out = sys.argv[1], sys.argv[2]
envs, steps, min_time = 64, 32, 3.0
start = time.perf_counter()
env, params = make("fresh", size=size)
make_s = time.perf_counter() - start
keys = jax.random.split(jax.random.key(0), envs)
start = time.perf_counter()
obs, states = jax.block_until_ready(jax.jit(jax.vmap(env.reset, in_axes=(0, None)))(keys, params))
reset_s = time.perf_counter() - start
space = env.action_space(params)


def gymnax(carry, key):
    state, _, returns = carry
    k_act, k_step = jax.random.split(key)
    obs, state, reward, *_ = env.step(k_step, state, space.sample(k_act), params)
    return state, obs, returns + reward


carry = (states, obs, jnp.zeros(envs, jnp.float32))
compile_s, rate, calls = time_keyed(gymnax, carry, jax.random.split(jax.random.key(1), envs), steps, min_time)
record = {
    **environment_info(),
    "size": size,
    "levels": "fresh",
    "envs": envs,
    "steps": steps,
    "make_s": make_s,
    "first_reset_s": reset_s,
    "path": "gymnax",
    "compile_s": compile_s,
    "steps_per_s": rate,
    "calls": calls,
}
Path(out).write_text(json.dumps(record, indent=1))
print(json.dumps({k: record[k] for k in ("size", "make_s", "first_reset_s", "compile_s", "steps_per_s", "calls")}))
