"""Time SFL's scoring (refresh_buffer) of this tree: cpu-small's SFL settings, 7 timed calls after a warm-up.

Run from a tree's root with its src on the path: PYTHONPATH=src JAX_COMPILATION_CACHE_DIR= python score.py before
"""

import json
import sys
import time

import jax

from kinetix_cli.config import load_config
from kinetix_cli.env.factory import make_env
from kinetix_cli.rl.curricula.sfl import refresh_buffer
from kinetix_cli.rl.networks import make_network
from kinetix_cli.rl.pool import level_pool
from kinetix_cli.rl.ppo import init_runner

config = load_config("experiments/cpu-small.yaml", ["curriculum.name=sfl"])
env, env_params = make_env(config.env)
network = make_network(config.model, config.env)
pool = level_pool(config)
runner = init_runner(env, network, config.ppo, pool, jax.random.key(0), buffer_size=config.curriculum.buffer_size)


def call(k: int):
    parts = {"env": env, "network": network, "fresh": None, "curriculum": config.curriculum}
    return refresh_buffer(runner.params, env_params, pool, jax.random.key(k), **parts, buffer=runner.buffer, update=k)


start = time.perf_counter()
jax.block_until_ready(call(0))
compile_s = time.perf_counter() - start
times = []
for k in range(1, 8):
    start = time.perf_counter()
    jax.block_until_ready(call(k))
    times.append(time.perf_counter() - start)
median = sorted(times)[len(times) // 2]
record = {"tree": sys.argv[1], "compile_s": round(compile_s, 2), "times": [round(x, 3) for x in times]}
print(json.dumps(record | {"median": round(median, 3)}))
