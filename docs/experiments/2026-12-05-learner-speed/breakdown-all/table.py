"""The breakdown table of every model at s and m from s.json and m.json next to this script (run.sh's records):
update env steps/s, the environment alone, the learning epochs' share, FLOP/s of the update and of its epochs, and
the float32 matmul limit measured in the same process. Run: python table.py"""

import json
from pathlib import Path

HERE = Path(__file__).parent
COLUMNS = "size, model, update env steps/s, env alone, learn share, update GFLOP/s, learn GFLOP/s, f32 limit, of it"

print("| " + " | ".join(COLUMNS.split(", ")) + " |")
print("|---" * len(COLUMNS.split(", ")) + "|")
for size in ("s", "m"):
    path = HERE / f"{size}.json"
    if not path.exists():
        continue
    for r in json.loads(path.read_text())["results"]:
        b = r["breakdown"]
        learn = next(p for p in b["phases"] if p["name"] == "learn")
        cells = [
            size,
            r["model"],
            f"{r['steps_per_s']:,.0f}",
            f"{b['env_only_steps_per_s']:,.0f}",
            f"{learn['share']:.0%}",
            f"{b['update_gflop_per_s']:.1f}",
            f"{b['learn_gflop_per_s']:.1f}",
            f"{b['f32_limit_gflop_per_s']:.1f}",
            f"{b['f32_limit_share']:.0%}",
        ]
        print("| " + " | ".join(cells) + " |")
