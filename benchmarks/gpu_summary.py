"""The tables of benchmarks/gpu.sh for BENCHMARKS.md, from the files it wrote.

    python benchmarks/gpu_summary.py OUT_DIR
    python benchmarks/gpu_summary.py --sfl-steps TRAIN_JSON SECONDS [--set KEY=VALUE ...]

The second form prints the `ppo.total_timesteps` of the SFL run: the whole updates of experiments/pretrain-s.yaml
(with the overrides) that the transformer's measured training rate fits into SECONDS.
"""

from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path

from kinetix_cli.config import load_config

SFL_CONFIG = Path("experiments/pretrain-s.yaml")


def sfl_steps(train_json: Path, seconds: float, overrides: list[str]) -> int:
    config = load_config(SFL_CONFIG, overrides)
    rate = next(r["steps_per_s"] for r in _read(train_json)["results"] if r["model"] == "transformer")
    updates = max(2, int(rate * seconds / config.ppo.batch_size))
    return updates * config.ppo.batch_size


def summary(out: Path) -> str:
    engine, train = _read(out / "engine-m.json"), _read(out / "train-m.json")
    m = engine["machine"]
    lines = [f"{engine['date']}; {m['device']}, {m['cpu_count']} CPUs; {_versions(engine['versions'])}", ""]
    lines += ["| engine, size m | envs | compile [s] | steps/s | ours / jax2d |", "| --- | ---: | ---: | ---: | ---: |"]
    ours = {r["envs"]: r["steps_per_s"] for r in engine["results"] if r["engine"] == "kinetix"}
    for r in engine["results"]:
        ratio = f"{ours[r['envs']] / r['steps_per_s']:.1f}x" if r["engine"] == "jax2d" else ""
        lines.append(f"| {r['engine']} | {r['envs']:,} | {r['compile_s']:.1f} | {r['steps_per_s']:,.0f} | {ratio} |")
    c = train["config"]
    update = f"{c['num_steps']} steps x {c['epochs']} epochs x {c['minibatches']} minibatches"
    lines += ["", f"PPO updates at size m: {update}"]
    lines += ["", "| model | envs | parameters | compile [s] | env steps/s |", "| --- | ---: | ---: | ---: | ---: |"]
    for r in train["results"]:
        lines.append(
            f"| {r['model']} | {r['envs']:,} | {r['parameters']:,} | {r['compile_s']:.1f} | {r['steps_per_s']:,.0f} |"
        )
    lines += ["", *_paper(engine, _read(out / "train-m-paper.json"))]
    if (out / "sfl").is_dir():
        lines += ["", *_sfl(out / "sfl")]
    return "\n".join(lines)


PAPER = {"engine": (16_384, 9.0e6), "train": (32_768, 824e3)}
"""The paper's speed figures at size m on an L40S: (envs, steps/s) of its engine and of its RL loop (transformer)."""


def _paper(engine: dict, train: dict) -> list[str]:
    """Our engine and transformer PPO beside the paper's figures, at the largest sizes measured."""
    ours = max((r for r in engine["results"] if r["engine"] == "kinetix"), key=lambda r: r["envs"])
    ppo = max((r for r in train["results"] if r["model"] == "transformer"), key=lambda r: r["envs"])
    rows = [("engine", ours, PAPER["engine"]), ("PPO, transformer", ppo, PAPER["train"])]
    lines = ["| at the paper's sizes, m | our envs | our steps/s | paper's envs | paper's steps/s (L40S) |"]
    lines.append("| --- | ---: | ---: | ---: | ---: |")
    for name, r, (envs, rate) in rows:
        lines.append(f"| {name} | {r['envs']:,} | {r['steps_per_s']:,.0f} | {envs:,} | {rate:,.0f} |")
    return lines


def _sfl(run: Path) -> list[str]:
    records = [json.loads(line) for line in (run / "metrics.jsonl").read_text().splitlines() if line.strip()]
    last = records[-1]
    steady = statistics.median(r["sps"] for r in records[1:]) if len(records) > 1 else records[0]["sps"]
    wall = int((run / "wall_seconds").read_text())
    evaluation = _read(run / "eval.json")
    suites = ", ".join(f"{name} {s['solve_rate']:.1%}" for name, s in evaluation["suites"].items())
    return [
        "| SFL, transformer, size s | |",
        "| --- | --- |",
        f"| updates | {last['update']} ({last['steps']:,} env steps trained, {last['total_steps']:,} with scoring) |",
        f"| median update rate (after the first) | {steady:,.0f} env steps/s |",
        f"| wall clock (compile, scoring and saving included) | {wall} s |",
        f"| zero-shot solve rate ({evaluation['attempts']} attempts per level) | {suites} |",
    ]


def _versions(versions: dict) -> str:
    return ", ".join(f"{k} {v}" for k, v in versions.items() if k in ("kinetix", "jax", "jaxlib", "flax", "jax2d"))


def _read(path: Path) -> dict:
    return json.loads(path.read_text())


if __name__ == "__main__":
    if sys.argv[1] == "--sfl-steps":
        overrides = [arg for arg in sys.argv[4:] if arg != "--set"]
        print(sfl_steps(Path(sys.argv[2]), float(sys.argv[3]), overrides))
    else:
        print(summary(Path(sys.argv[1])))
