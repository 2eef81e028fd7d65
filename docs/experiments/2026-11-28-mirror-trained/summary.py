"""The trained-equivariance table: per arm (plain: the batch-scale study's 256 arm; geometric: model.mirror) and seed,
the validation mean (all 180, per size), the plain runs' gap to the mirror images, training wall time; per arm mean
and standard deviation over seeds. Run from the repository root."""

from __future__ import annotations

import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent
BASE = HERE.parent / "2026-11-28-batch-scale"


def rates(path: Path) -> dict[tuple[str, str], float]:
    return {(r["size"], Path(r["level"]).stem): r["solve_rate"] for r in json.loads(path.read_text())["levels"]}


def main() -> None:
    print("| arm | seed | all 180 | s | m | l | mean gap to mirror image | training wall time |")
    print("|---|---|---|---|---|---|---|---|")
    means: dict[str, list[float]] = {}
    for arm, folder, name in (("plain", BASE, "steps-256-{}"), ("geometric", HERE, "geometric-{}")):
        for seed in (0, 1, 2):
            record = folder / f"{name.format(seed)}.json"
            if not record.is_file():
                continue
            result = rates(record)
            sizes = [100 * statistics.mean(v for (z, _), v in result.items() if z == size) for size in "sml"]
            gap = ""
            image = HERE / f"plain-{seed}-mirrorimage.json"
            if arm == "plain" and image.is_file():
                mirrored = rates(image)
                gap = f"{100 * statistics.mean(abs(result[k] - mirrored[k]) for k in result):.1f}"
            wall = float((folder / f"{name.format(seed)}.time").read_text().split()[0])
            total = 100 * statistics.mean(result.values())
            means.setdefault(arm, []).append(total)
            cells = " | ".join(f"{x:.1f}%" for x in sizes)
            print(f"| {arm} | {seed} | {total:.1f}% | {cells} | {gap} | {wall:.0f} s |")
    for arm, values in means.items():
        spread = statistics.stdev(values) if len(values) > 1 else float("nan")
        print(f"\n{arm}: mean {statistics.mean(values):.2f}%, sd {spread:.2f} over {len(values)} seeds")


if __name__ == "__main__":
    main()
