# The 120 held-out generated levels (40 per size, generate --seed 777, trivial ones dropped) as level files in
# runs/heldout/{s,m,l}: the selection set for general v2 candidates (not the paper levels). ~5.5 min.
set -e
# (Run here with a Python loop over kinetix_cli.levels.export; the same files, named <set>-00000.json, come from
#  `kinetix levels export runs/heldout-set-S --first 40 -o runs/heldout/S`, added after these runs.)
cd "$(dirname "$0")/../.."
for size in s m l; do
  .venv/bin/kinetix generate --size $size --count 40 --seed 777 --out runs/heldout-set-$size > runs/heldout-gen-$size.log 2>&1
done
.venv/bin/python - <<'PY'
from pathlib import Path
from engine import SIZES
from kinetix_cli.levels.export import export_level
from kinetix_cli.levels.files import save_level
from kinetix_cli.levels.levelset import level_at, load_levelset
for size in "sml":
    ls = load_levelset(Path(f"runs/heldout-set-{size}"))
    out = Path(f"runs/heldout/{size}"); out.mkdir(parents=True, exist_ok=True)
    for i in range(40):
        save_level(out / f"g{i:02d}.json", export_level(level_at(ls, i), SIZES[size], name=f"g{i}", description="held-out generated"))
print("exported")
PY
