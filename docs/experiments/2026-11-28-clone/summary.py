"""Lever 2's table from the records beside this file: per arm and seed, the cloning steps and their time, the PPO
updates and env steps trained, the validation mean (all 180 and the 50 s levels), the test means (the paper's 74
levels at evaluation seeds 1000 and 1001, read after the decision, where recorded) and the training wall time; per
arm the mean and standard deviation over seeds, and PLAN.md's rule (an arm beats P if its seed mean exceeds P's by
more than the larger of the two sds); then RERUN.md's check (seed 3, a fresh clone), where its records are here.
Run from the repository root: python docs/experiments/2026-11-28-clone/summary.py"""

from __future__ import annotations

import gzip
import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent
ARMS = {"P": "PPO alone, 30 min", "C": "cloning then PPO", "L": "PPO + cloning loss"}


def _mean(path: Path, size: str | None = None) -> float:
    levels = json.loads(path.read_text())["levels"]
    return 100 * statistics.mean(r["solve_rate"] for r in levels if size is None or r["size"] == size)


def _lines(path: Path) -> list[dict]:
    """The JSON lines of `path`, or of its gzipped copy `path.gz` (none: [])."""
    if path.is_file():
        text = path.read_text()
    elif path.with_name(path.name + ".gz").is_file():
        text = gzip.decompress(path.with_name(path.name + ".gz").read_bytes()).decode()
    else:
        return []
    return [json.loads(line) for line in text.splitlines() if line.strip()]


def _spread(values: list[float]) -> float:
    return statistics.stdev(values) if len(values) > 1 else float("nan")


def _summary(values: list[float]) -> str:
    return f"mean {statistics.mean(values):.2f}%, sd {_spread(values):.2f} over {len(values)} seeds"


def main() -> None:
    solver = sum(float((HERE / f"{n}.time").read_text().split()[0]) for n in ("generate", "solve"))
    print(f"solved set: {solver:.1f} s of generating and solving (S = {solver / 60:.2f} min)\n")
    print(
        "| arm | seed | cloning steps | cloning time | PPO updates | env steps | validation, all 180 | s (50) "
        "| test, all 74 (seeds 1000 / 1001) | wall time |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    means, tests = {}, {}
    for seed in (0, 1, 2):
        for arm, name in ARMS.items():
            record = HERE / f"{arm}-{seed}.json"
            if not record.is_file():
                continue
            cloned = _lines(HERE / f"{arm}-{seed}.clone.jsonl")
            metrics = _lines(HERE / f"{arm}-{seed}.metrics.jsonl")
            wall = float((HERE / f"{arm}-{seed}.time").read_text().split()[0])
            test_means = []
            for eval_seed in (1000, 1001):
                test = HERE / f"test-{arm}-{seed}-{eval_seed}.json"
                if test.is_file():
                    test_means.append(_mean(test))
                    tests.setdefault((arm, eval_seed), []).append(test_means[-1])
            test_mean = " / ".join(f"{value:.1f}%" for value in test_means)
            means.setdefault(arm, []).append(_mean(record))
            print(
                f"| {arm} ({name}) | {seed} | {len(cloned)} | {sum(r['seconds'] for r in cloned):.0f} s "
                f"| {len(metrics)} | {metrics[-1]['steps'] / 1e6:.2f}M | {_mean(record):.1f}% "
                f"| {_mean(record, 's'):.1f}% | {test_mean} | {wall:.0f} s |"
            )
    print()
    for arm, values in means.items():
        print(f"{arm}: validation {_summary(values)}")
    for (arm, eval_seed), values in tests.items():
        print(f"test (evaluation seed {eval_seed}), {arm}: {_summary(values)}")
    if len(means.get("P", [])) < 3:
        print("\nthe rule waits for P's three seeds")
        return
    p = means["P"]
    for arm in ("C", "L"):
        if len(means.get(arm, [])) < 3:
            print(f"\n{arm}: the rule waits for its three seeds")
            continue
        gap, bar = statistics.mean(means[arm]) - statistics.mean(p), max(_spread(means[arm]), _spread(p))
        verdict = "beats P" if gap > bar else "does not beat P"
        print(f"\n{arm} - P = {gap:+.2f} points against the larger sd {bar:.2f}: {arm} {verdict}")
    _rerun(means)


def _rerun(means: dict) -> None:
    """RERUN.md's checks on the seed-3 runs from a fresh clone (the arms recorded so far), and the four-seed means."""
    if not (HERE / "rerun-P-3.json").is_file():
        return
    solver = sum(float((HERE / f"rerun-{n}.time").read_text().split()[0]) for n in ("generate", "solve"))
    print(f"\nre-run, seed 3, fresh clone: its solved set {solver:.1f} s (S = {solver / 60:.2f} min)")
    print(f"  {(HERE / 'rerun-solved-info.txt').read_text().splitlines()[1].strip()}")
    study = {"gen-s": "bc59bec6", "solved-s": "56d565cc"}
    for line in (HERE / "rerun-sha256.txt").read_text().splitlines():
        digest, path = line.split()
        name = Path(path).parent.name
        same = "same as" if digest.startswith(study[name]) else "differs from"
        print(f"  {name} shard sha256 {digest[:8]}: {same} the study's")
    print("\n| seed 3, fresh clone | env steps | all 180 | s (50) | m (60) | l (70) | wall time |")
    print("|---|---|---|---|---|---|---|")
    scores = {}
    for arm in ARMS:
        record = HERE / f"rerun-{arm}-3.json"
        if not record.is_file():
            continue
        scores[arm] = _mean(record)
        steps = _lines(HERE / f"rerun-{arm}-3.metrics.jsonl")[-1]["steps"]
        wall = float((HERE / f"rerun-{arm}-3.time").read_text().split()[0])
        sizes = " | ".join(f"{_mean(record, z):.1f}%" for z in "sml")
        print(f"| {arm} | {steps / 1e6:.2f}M | {scores[arm]:.2f}% | {sizes} | {wall:.0f} s |")
    for arm in ("C", "L"):
        if arm in scores:
            lead = scores[arm] - scores["P"]
            four = statistics.mean([*means[arm], scores[arm]]) - statistics.mean([*means["P"], scores["P"]])
            print(
                f"no win holds for {arm}: {lead <= 2.00} ({arm} - P = {lead:+.2f} points, margin 2.00; "
                f"four-seed means {statistics.mean([*means[arm], scores[arm]]):.2f}% against "
                f"{statistics.mean([*means['P'], scores['P']]):.2f}%, {four:+.2f})"
            )


if __name__ == "__main__":
    main()
