"""general v1 with its action logits divided by T (the actor output layer scaled by 1/T), as an agent folder.

.venv/bin/python benchmarks/general-v3-cpu-2026-11-27/temper.py general T OUT
"""

import sys
from pathlib import Path

import jax
import numpy as np

from kinetix_cli.rl.agents import _write_agent, load_policy
from kinetix_cli.rl.train import POLICY_HEAD, _replace_subtrees

src, T, out = sys.argv[1], float(sys.argv[2]), Path(sys.argv[3])
p = load_policy(src)
params = jax.tree.map(np.asarray, p.params)
scaled = jax.tree.map(lambda x: np.asarray(x / T, np.float32), params)
params = _replace_subtrees(params, scaled, POLICY_HEAD)
_write_agent(
    out,
    p.config,
    params,
    name="tmp",
    version=1,
    trained={"run": f"{src} T={T}", "update": p.update, "steps": 0, "commands": []},
    evaluation={},
)
print("wrote", out)
