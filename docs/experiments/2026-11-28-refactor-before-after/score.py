"""Time SFL's scoring (refresh_buffer) of this tree: cpu-small's SFL settings, 5 timed calls after a warm-up."""
import json, sys, time
import jax
from kinetix_cli.config import load_config
from kinetix_cli.env.factory import make_env
from kinetix_cli.rl.networks import make_network
from kinetix_cli.rl.pool import fresh_source, level_pool
from kinetix_cli.rl.ppo import init_runner
from kinetix_cli.rl.curricula.sfl import refresh_buffer

config = load_config("experiments/cpu-small.yaml", ["curriculum.name=sfl"])
env, env_params = make_env(config.env)
network = make_network(config.model, config.env)
pool = level_pool(config)
runner = init_runner(env, network, config.ppo, pool, jax.random.key(0), buffer_size=config.curriculum.buffer_size)
call = lambda k: refresh_buffer(runner.params, env_params, pool, jax.random.key(k), env=env, network=network, fresh=None,
                                curriculum=config.curriculum, buffer=runner.buffer, update=k)
t = time.perf_counter(); jax.block_until_ready(call(0)); compile_s = time.perf_counter() - t
times = []
for k in range(1, 8):
    t = time.perf_counter(); jax.block_until_ready(call(k)); times.append(time.perf_counter() - t)
print(json.dumps({"tree": sys.argv[1], "compile_s": round(compile_s, 2), "times": [round(x, 3) for x in times],
                  "median": round(sorted(times)[len(times) // 2], 3)}))
