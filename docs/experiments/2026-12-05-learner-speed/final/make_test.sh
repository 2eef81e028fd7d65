#!/bin/bash
# README.md here, second part: a fresh clone's `make test`, warm, cold (an empty suite compile cache), warm again.
set -uo pipefail
cd "$(dirname "$0")/../../../.."
HERE=$PWD/docs/experiments/2026-12-05-learner-speed/final
CLONE=$(mktemp -d); git clone -q . $CLONE; cd $CLONE
echo "== $(git rev-parse --short HEAD) in $CLONE, $(date -u +%F\ %T) UTC" | tee -a $HERE/make_test.txt
for run in warm cold warm-again; do
  EXTRA=""; [ $run = cold ] && EXTRA="KINETIX_TEST_CACHE=$(mktemp -d)"
  start=$(date +%s.%N)
  make test $EXTRA > /tmp/make-test-$run.log 2>&1; rc=$?
  end=$(date +%s.%N)
  printf "%-10s rc %d %6.1f s  %s  %s\n" $run $rc "$(echo "$end - $start" | bc)" "$(date -u +%T)" \
    "$(grep -E '[0-9]+ passed' /tmp/make-test-$run.log | tail -1)" | tee -a $HERE/make_test.txt
done
