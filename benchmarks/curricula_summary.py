"""Summarise benchmarks/curricula.sh, or size one of its runs.

    python curricula_summary.py OUT_DIR
        per curriculum and suite: the zero-shot solve rate of every seed, their mean and spread (sample standard
        deviation), and each run's environment steps (scoring included) from its metrics.jsonl.
    python curricula_summary.py --training-steps BUDGET --config FILE --set KEY=VALUE ...
        prints ppo.total_timesteps for a run of that config whose updates plus scoring rollouts make at most
        BUDGET environment steps (SFL scores `scoring_steps` before every `refresh_every`-th update).
"""

import json
import math
import statistics
import sys
from pathlib import Path


def training_steps(budget: int, args: list[str]) -> int:
    from kinetix_cli.config import load_config

    config_file = args[args.index("--config") + 1]
    overrides = [args[i + 1] for i, a in enumerate(args) if a == "--set"]
    config = load_config(config_file, [*overrides, f"ppo.total_timesteps={budget}"])
    batch, curriculum = config.ppo.batch_size, config.curriculum
    if curriculum.name != "sfl":
        return budget
    updates = budget // batch
    while updates * batch + math.ceil(updates / curriculum.refresh_every) * curriculum.scoring_steps > budget:
        updates -= 1
    return updates * batch


def summary(out: Path) -> None:
    runs: dict[str, list[Path]] = {}
    for run in sorted(p for p in out.iterdir() if (p / "eval.json").exists()):
        runs.setdefault(run.name.rsplit("-", 1)[0], []).append(run)
    print("| curriculum | suite | solve rate per seed | mean | spread (sd) | env steps per run (scoring included) |")
    print("|---|---|---|---|---|---|")
    for curriculum, members in runs.items():
        evals = [json.loads((r / "eval.json").read_text()) for r in members]
        totals = []
        for r in members:
            last = json.loads((r / "metrics.jsonl").read_text().splitlines()[-1])
            totals.append(last.get("total_steps", last["steps"]))
        steps = ", ".join(f"{t / 1e6:.2f}M" for t in totals)
        for suite in evals[0]["suites"]:
            rates = [e["suites"][suite]["solve_rate"] for e in evals]
            seeds = " / ".join(f"{r:.1%}" for r in rates)
            spread = statistics.stdev(rates) if len(rates) > 1 else float("nan")
            print(f"| {curriculum} | {suite} | {seeds} | {statistics.mean(rates):.1%} | {spread:.1%} | {steps} |")


if __name__ == "__main__":
    if sys.argv[1] == "--training-steps":
        print(training_steps(int(sys.argv[2]), sys.argv[3:]))
    else:
        summary(Path(sys.argv[1]))
