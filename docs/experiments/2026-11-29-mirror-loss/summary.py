"""The symmetry-loss table from the records beside this file (and the plain arm's in ../2026-11-28-batch-scale/):
per arm and seed the env steps trained, the steady env steps per second, the validation mean (all 180 and per size),
the mean per-level gap between a level and its mirror image, and the test means where recorded (read after the
decision); per arm the mean and sd over seeds, and PLAN.md's rule; then RERUN.md's check (seed 3, a fresh clone).
Run from the repository root: python docs/experiments/2026-11-29-mirror-loss/summary.py"""

from __future__ import annotations

import gzip
import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent
PLAIN = HERE.parent / "2026-11-28-batch-scale"


def _rates(path: Path) -> dict[tuple[str, str], float] | None:
    if not path.is_file():
        return None
    return {(r["size"], Path(r["level"]).stem): r["solve_rate"] for r in json.loads(path.read_text())["levels"]}


def _mean(rates: dict, size: str | None = None) -> float:
    return 100 * statistics.mean(v for (z, _), v in rates.items() if size is None or z == size)


def _training(metrics: Path) -> tuple[int, float]:
    """Env steps trained and the steady env steps/s (the median over updates after the first 10)."""
    zipped = metrics.with_name(metrics.name + ".gz")
    text = metrics.read_text() if metrics.is_file() else gzip.decompress(zipped.read_bytes()).decode()
    records = [json.loads(line) for line in text.splitlines() if line.strip()]
    rates = [r["sps"] for r in records[10:]]
    return records[-1]["steps"], statistics.median(rates) if rates else float("nan")


def _runs(arm: str):
    for seed in (0, 1, 2):
        if arm == "Y":
            yield seed, HERE / f"Y-{seed}.json", HERE / f"Y-{seed}.metrics.jsonl", HERE / f"Y-{seed}-mirrorimage.json"
        else:
            yield (
                seed,
                PLAIN / f"minutes-256-{seed}.json",
                PLAIN / f"minutes-256-{seed}.metrics.jsonl",
                HERE / f"plain-{seed}-mirrorimage.json",
            )


def main() -> None:
    print(
        "| arm | seed | env steps | env steps/s | all 180 | s | m | l | mean gap to mirror image | test (1000 / 1001) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    means = {}
    for arm in ("plain", "Y"):
        scores, test_scores = [], {1000: [], 1001: []}
        for seed, record, metrics, image in _runs(arm):
            rates = _rates(record)
            if rates is None:
                continue
            found = metrics.is_file() or metrics.with_name(metrics.name + ".gz").is_file()
            steps, speed = _training(metrics) if found else (0, float("nan"))
            mirror = _rates(image)
            gap = f"{100 * statistics.mean(abs(rates[k] - mirror[k]) for k in rates):.1f}" if mirror else ""
            tests = [_rates(HERE / f"test-{arm}-{seed}-{s}.json") for s in (1000, 1001)]
            test = " / ".join(f"{_mean(t):.1f}%" for t in tests if t is not None)
            for eval_seed, t in zip((1000, 1001), tests, strict=True):
                if t is not None:
                    test_scores[eval_seed].append(_mean(t))
            sizes = " | ".join(f"{_mean(rates, z):.1f}%" for z in "sml")
            scores.append(_mean(rates))
            print(
                f"| {arm} | {seed} | {steps / 1e6:.2f}M | {speed:,.0f} | {scores[-1]:.1f}% | {sizes} | {gap} | {test} |"
            )
        if scores:
            spread = statistics.stdev(scores) if len(scores) > 1 else float("nan")
            means[arm] = (statistics.mean(scores), spread, len(scores))
            test = " / ".join(
                f"{statistics.mean(v):.2f}% ({statistics.stdev(v):.2f})" for v in test_scores.values() if len(v) > 1
            )
            print(f"| {arm} | mean (sd) | | | {means[arm][0]:.2f}% ({spread:.2f}) | | | | | {test} |")
    if len(means) == 2 and means["Y"][2] == means["plain"][2] == 3:
        margin = max(means["Y"][1], means["plain"][1])
        wins = means["Y"][0] - means["plain"][0] > margin
        print(
            f"\nrule: Y - plain = {means['Y'][0] - means['plain'][0]:+.2f} points, margin {margin:.2f}: "
            f"{'Y wins' if wins else 'Y does not win'}"
        )
    _rerun(means)


def _rerun(means: dict) -> None:
    """RERUN.md's two checks on the seed-3 pair, and the four-seed means."""
    pair = {
        arm: (_rates(HERE / f"rerun-{arm}-3.json"), _rates(HERE / f"rerun-{arm}-3-mirrorimage.json")) for arm in means
    }
    if any(rates is None or image is None for rates, image in pair.values()):
        return
    print("\n| seed 3, fresh clone | env steps | all 180 | s | m | l | mean gap to mirror image | 50+ points apart |")
    print("|---|---|---|---|---|---|---|---|")
    gaps = {}
    for arm, (rates, image) in pair.items():
        steps, _ = _training(HERE / f"rerun-{arm}-3.metrics.jsonl")
        gaps[arm] = 100 * statistics.mean(abs(rates[k] - image[k]) for k in rates)
        apart = sum(abs(rates[k] - image[k]) >= 0.5 for k in rates)
        sizes = " | ".join(f"{_mean(rates, z):.1f}%" for z in "sml")
        print(f"| {arm} | {steps / 1e6:.2f}M | {_mean(rates):.2f}% | {sizes} | {gaps[arm]:.1f} | {apart} |")
    lead = _mean(pair["Y"][0]) - _mean(pair["plain"][0])
    print(f"\nno win holds: {lead <= 0.90} (Y - plain = {lead:+.2f} points, margin 0.90)")
    print(f"the gap holds: {gaps['Y'] < 0.6 * gaps['plain']} (Y's gap {gaps['Y'] / gaps['plain']:.2f}x plain's)")


if __name__ == "__main__":
    main()
