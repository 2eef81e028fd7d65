"""Median seconds per update (without SFL scoring: updates 1-63, 65-127) of each variant's metrics here."""

import json
import statistics
from pathlib import Path

HERE = Path(__file__).parent

for path in sorted(HERE.glob("metrics-*.jsonl")):
    rows = [json.loads(line) for line in path.open() if '"sps"' in line]
    seconds = [256 * 32 / row["sps"] for i, row in enumerate(rows) if i % 64]
    print(f"{path.stem.removeprefix('metrics-')}: {len(rows)} updates, median {statistics.median(seconds):.3f} s")
