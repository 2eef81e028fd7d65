"""Policy entropy at each level's first observation, every action entry vs only the entries the level uses.

Used on the GPU SFL run's checkpoint (sfl-run, brought back from the GPU machine, not kept in git):
    .venv/bin/python benchmarks/gpu-h100-2026-11-27b/first_entropy.py RUN_DIR .cache/reference-levels/s
"""

import dataclasses
import glob
import sys

import jax
import numpy as np

from kinetix_cli.env.factory import make_env_for_level
from kinetix_cli.levels.files import load_level
from kinetix_cli.rl.checkpoints import read_policy
from kinetix_cli.rl.networks import make_network

config, params, where = read_policy(sys.argv[1])
print(where, config.model.name, "mask in run:", config.model.mask_unused_actions)
rows = []
for f in sorted(glob.glob(sys.argv[2] + "/*.json")):
    level = load_level(f)
    out = []
    for mask in (False, True):
        model = dataclasses.replace(config.model, mask_unused_actions=mask)
        env, env_params = make_env_for_level(config.env, "s", f)
        net = make_network(model, config.env)
        lvl = level.build(env.static)
        obs, state = env.reset_to_level(lvl)
        dist, _ = net.apply(params, jax.tree.map(lambda x: x[None], obs))
        out.append(float(dist.entropy()[0]))
        if mask:
            out.append(float(np.log(np.isfinite(np.asarray(dist.logits[0])).sum(-1)).sum()))
    rows.append(out)
    print(f.split("/")[-1], "all entries {:.2f}  used entries {:.2f} of uniform {:.2f}".format(*tuple(out)))
r = np.array(rows)
print("mean: all {:.2f} used {:.2f} of uniform {:.2f} nats".format(*tuple(r.mean(0))))
