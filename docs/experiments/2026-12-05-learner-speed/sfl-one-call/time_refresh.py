"""Time one SFL refresh (`rl.curricula.sfl.refresh_buffer`) of the general recipe (experiments/general.yaml: 384
fresh s candidates drawn 128 to a key, 2 copies x 256 steps each, rel-mlp 64) on a mesh of every CPU device
`kinetix` splits the CPU into, as a training run calls it: the compile with the first call, then the median of
CALLS calls with new keys. Prints one JSON line. Run with the source to measure on PYTHONPATH:
python time_refresh.py CALLS"""

import json
import statistics
import sys
import time

from kinetix_cli import cpu

cpu.split()  # as `kinetix` does: one JAX device per core (KINETIX_CPU_DEVICES=1 for one)

import jax  # noqa: E402

from kinetix_cli.config.loader import load_config  # noqa: E402
from kinetix_cli.env.factory import make_env  # noqa: E402
from kinetix_cli.parallel import make_mesh, replicate, using  # noqa: E402
from kinetix_cli.rl.curricula.sfl import refresh_buffer  # noqa: E402
from kinetix_cli.rl.networks import training_network  # noqa: E402
from kinetix_cli.rl.pool import fresh_source  # noqa: E402
from kinetix_cli.rl.ppo import init_runner  # noqa: E402

calls = int(sys.argv[1])
config = load_config("experiments/general.yaml")
mesh = make_mesh(None)
with using(mesh):
    fresh = fresh_source(config)
    env, env_params = make_env(config.env, pairs=config.trains_on_pairs, attention=config.model.reads_attention)
    network = training_network(config)
    key = replicate(jax.random.key(0), mesh)
    runner = init_runner(env, network, config.ppo, None, key, fresh=fresh, buffer_size=config.curriculum.buffer_size)
    env_params = replicate(env_params, mesh)
    parts = {"env": env, "network": network, "fresh": fresh, "curriculum": config.curriculum}

    def refresh(i):
        start = time.perf_counter()
        k = replicate(jax.random.key(100 + i), mesh)
        buffer = refresh_buffer(runner.params, env_params, None, k, **parts, buffer=runner.buffer, update=i)
        jax.block_until_ready(buffer)
        return time.perf_counter() - start, float(buffer.solve_rate.mean())

    first, _ = refresh(0)
    timed = [refresh(i) for i in range(1, calls + 1)]
print(
    json.dumps(
        {
            "devices": mesh.size,
            "first_call_s": round(first, 3),
            "median_s": round(statistics.median(t for t, _ in timed), 3),
            "calls_s": [round(t, 3) for t, _ in timed],
            "buffer_solve_rate": [round(r, 4) for _, r in timed],
        }
    )
)
