"""Per-size solve rates of `kinetix eval --json` files, and the held-out mean weighted like the paper's 10/24/40 levels.

python benchmarks/general-v4-cpu-2026-11-28/summary.py benchmarks/general-v4-cpu-2026-11-28/*-[hp]*.json
"""

import json
import sys
from pathlib import Path

for path in sys.argv[1:]:
    suites = json.loads(Path(path).read_text())["suites"]
    rate = {name.rsplit("/", 1)[-1]: 100 * suite["solve_rate"] for name, suite in suites.items()}
    weighted = (10 * rate["s"] + 24 * rate["m"] + 40 * rate["l"]) / 74
    print(
        f"{path:70s} s {rate['s']:5.1f} m {rate['m']:5.1f} l {rate['l']:5.1f} all {rate['all']:5.1f}"
        f" paper-weighted {weighted:5.1f}"
    )
