"""Print this folder's two tables from run.sh's records: the speed of 11c143b, HEAD and HEAD at one epoch per round,
and every model's breakdown at s and m. Run: python summary.py"""

import json
from pathlib import Path

HERE = Path(__file__).parent


def load(name: str) -> dict:
    return json.loads((HERE / f"{name}.json").read_text())


print("| round | 11c143b, 4 x 4 | HEAD, 4 x 4 | HEAD, 1 x 16 |")
print("|---|---|---|---|")
for round_ in (1, 2):
    rates = [load(f"speed-{side}-{round_}")["results"][0]["steps_per_s"] for side in ("before", "head", "one-epoch")]
    cells = [f"{rates[0]:,.0f}"] + [f"{rate:,.0f} ({rate / rates[0]:.2f}x)" for rate in rates[1:]]
    print(f"| {round_} | " + " | ".join(cells) + " |")

print()
COLUMNS = "size, model, update env steps/s, env alone, learn share, update GFLOP/s, learn GFLOP/s, f32 limit, of it"
print("| " + " | ".join(COLUMNS.split(", ")) + " |")
print("|---" * len(COLUMNS.split(", ")) + "|")
for size in ("s", "m"):
    for result in load(f"breakdown-{size}")["results"]:
        b = result["breakdown"]
        learn = next(phase for phase in b["phases"] if phase["name"] == "learn")
        print(
            f"| {size} | {result['model']} | {result['steps_per_s']:,.0f} | {b['env_only_steps_per_s']:,.0f} "
            f"| {learn['share']:.0%} | {b['update_gflop_per_s']:.1f} | {b['learn_gflop_per_s']:.1f} "
            f"| {b['f32_limit_gflop_per_s']:.1f} | {b['f32_limit_share']:.0%} |"
        )
