"""Issue 70's GPU part (run.sh): the SFL runs' figures from the folder that came back, as a markdown table.

    python summary.py FOLDER

Per run (cold: empty compile cache; cached: the same command again in a new process): the process's wall time, the
first update (compile or cache read, the first refresh, the update), the plain updates' median, and SFL's share of
the run: the refresh updates' time beyond a plain update over all updates but the first (as ../one-epoch/)."""

from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path

REFRESH_EVERY = 4


def figures(folder: Path, side: str) -> dict:
    rows = [json.loads(line) for line in (folder / f"metrics-{side}.jsonl").open() if '"sps"' in line]
    batch = rows[0]["steps"]
    seconds = [batch / row["sps"] for row in rows]
    plain = statistics.median(s for i, s in enumerate(seconds) if i % REFRESH_EVERY)
    share = sum(seconds[i] - plain for i in range(REFRESH_EVERY, len(seconds), REFRESH_EVERY)) / sum(seconds[1:])
    return {"updates": len(rows), "first": seconds[0], "plain": plain, "share": share, "batch": batch}


def main(folder: Path) -> None:
    walls = dict(line.split()[:2] for line in (folder / "walls.txt").open() if line.split()[0] in ("cold", "cached"))
    print("| run | wall [s] | first update [s] | plain update [s] | env steps/s (plain) | SFL's share |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for side in ("cold", "cached"):
        f = figures(folder, side)
        cells = [
            f"{float(walls[side]):.1f}",
            f"{f['first']:.1f}",
            f"{f['plain']:.3f}",
            f"{f['batch'] / f['plain']:,.0f}",
        ]
        print(f"| {side} | " + " | ".join(cells) + f" | {f['share']:.1%} |")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
