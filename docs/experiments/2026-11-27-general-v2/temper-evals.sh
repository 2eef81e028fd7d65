# general v1 at action temperatures 1, 0.7, 0.5, 0.3 (temper.py) on the held-out levels and the 74 paper levels.
# First: for T in 0.7 0.5 0.3; do .venv/bin/python benchmarks/general-v3-cpu-2026-11-27/temper.py general $T runs/temper/general-T$T; done
cd "$(dirname "$0")/../.."
for a in general runs/temper/general-T0.7 runs/temper/general-T0.5 runs/temper/general-T0.3; do
  n=$(basename $a)
  /usr/bin/time -f "$n heldout %e s" .venv/bin/kinetix eval $a --levels runs/heldout/s --levels runs/heldout/m --levels runs/heldout/l --attempts 20 --seed 2000 --json runs/temper/$n-heldout.json > runs/temper/$n-heldout.log 2>&1
done
for a in general runs/temper/general-T0.7 runs/temper/general-T0.5 runs/temper/general-T0.3; do
  n=$(basename $a)
  /usr/bin/time -f "$n paper %e s" .venv/bin/kinetix eval $a --levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l --attempts 50 --seed 1000 --json runs/temper/$n-paper.json > runs/temper/$n-paper.log 2>&1
done
echo ALLDONE
