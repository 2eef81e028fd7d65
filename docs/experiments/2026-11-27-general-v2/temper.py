"""general v1 with its action logits divided by T (the actor output layer scaled by 1/T), as an agent folder.

.venv/bin/python benchmarks/general-v3-cpu-2026-11-27/temper.py general T OUT

The same as `kinetix agents export general -o OUT --name tmp --temperature T`, which this script now calls.
"""

import sys

from kinetix_cli.rl.agents import export_agent

source, temperature, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
export_agent(source, out, name="tmp", version=1, commands=[], temperature=temperature)
print("wrote", out)
