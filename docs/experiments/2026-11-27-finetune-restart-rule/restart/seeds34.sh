#!/usr/bin/env bash
# issue 25: the restart rule with seeds it was not picked on: seeds 3 and 4 on rocket-car-jump and two-link-reach,
# the rule's arm (ft-v2-restart.sh) and scratch (general-s v2's network from scratch, the tables' settings).
set -euo pipefail
OUT=${OUT:-runs/ft-v2-seeds34} FIRST_SEEDS="3 4" REST_SEEDS="" \
  "$(dirname "$0")/seeds345.sh"
