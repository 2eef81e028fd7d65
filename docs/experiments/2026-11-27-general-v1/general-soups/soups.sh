#!/usr/bin/env bash
# general v2 blends (2026-11-27, issue 25): the parameters of general-s v2 averaged with those of runs fine-tuned
# from it (`kinetix agents blend`), each evaluated on all 74 paper levels, 50 attempts, evaluation seed 1000.
# Sources: general-s (v2) and general-m (v2, the second candidate, runs/general-v2b) are shipped; the other runs
# come from the candidates' scripts in benchmarks/general-v2*-cpu-2026-11-27/ (runs/general-v2b-seed1: second
# candidate, training seed 1; v2g seventh; v2f-seed0 sixth; v2h the entropy probe at update 434; general-v2m-seed0:
# general-s v2 at m for 25 minutes, general-v2m.sh 0 in this folder; general-v2n-seed1..3: general-s v2 at m for
# 400 updates, benchmarks/general-v2n-cpu-2026-11-27/general-v2n.sh 1, 2, 3).
# Usage: soups.sh OUT   (writes OUT/<blend>/ and OUT/eval-<blend>-1000.json)
set -euo pipefail
out=$1
kx=${KINETIX:-.venv/bin/kinetix}
levels=(--levels .cache/reference-levels/s --levels .cache/reference-levels/m --levels .cache/reference-levels/l)
blend() {  # NAME SOURCE... [--weight W]...
  local name=$1; shift
  $kx agents blend "$@" -o "$out/$name" --name "$name"
  $kx eval "$out/$name" "${levels[@]}" --attempts 50 --seed 1000 --json "$out/eval-$name-1000.json"
}
blend s-m-0.25 general-s general-m --weight 3 --weight 1
blend s-m-0.5 general-s general-m
blend s-m-0.75 general-s general-m --weight 1 --weight 3
blend gs-b1 general-s runs/general-v2b-seed1
blend gs-g general-s runs/general-v2g
blend gs-h general-s runs/general-v2h
blend gs-f general-s runs/general-v2f-seed0
blend gs-b-b1 general-s general-m runs/general-v2b-seed1 --weight 2 --weight 1 --weight 1
blend gs-all general-s general-m runs/general-v2b-seed1 runs/general-v2g runs/general-v2f-seed0 runs/general-v2h \
  --weight 5 --weight 1 --weight 1 --weight 1 --weight 1 --weight 1
blend gs-m0 general-s runs/general-v2m-seed0
blend gs-n1 general-s runs/general-v2n-seed1
blend gs-n2 general-s runs/general-v2n-seed2
blend gs-n123 general-s runs/general-v2n-seed1 runs/general-v2n-seed2 runs/general-v2n-seed3 \
  --weight 3 --weight 1 --weight 1 --weight 1
blend n1-n2 runs/general-v2n-seed1 runs/general-v2n-seed2
blend n123 runs/general-v2n-seed1 runs/general-v2n-seed2 runs/general-v2n-seed3
$kx eval "$out/s-m-0.5" "${levels[@]}" --attempts 50 --seed 1001 --json "$out/eval-s-m-0.5-1001.json"
# On the project's own hand-made levels (levels/s, m, l; 60 levels), evaluation seed 2000:
for p in general-s general-m "$out/s-m-0.25" "$out/s-m-0.5" "$out/s-m-0.75"; do
  $kx eval "$p" --levels levels/s --levels levels/m --levels levels/l --attempts 50 --seed 2000 \
    --json "$out/own-levels-$(basename "$p")-2000.json"
done
