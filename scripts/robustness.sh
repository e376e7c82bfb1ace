#!/usr/bin/env bash
# The long version of the settings table's property test (issue 48, item 2; docs/robustness.md,
# "The settings table"): the CI test SettingsProperty.EveryValueIsRefusedOrRunsEveryCycleFinite
# (tests/physics/test_settings_property.cpp) with more draws, the type's extremes and no budget,
# every (key, value, outcome) written to a CSV; then python3 -m vppdem.report robustness draws the outcomes
# per key into docs/robustness.md.
# usage: scripts/robustness.sh
# Knobs: SEED (48), DRAWS (values within each range per key, 4), JOBS (runs at once, 2),
#        TIMEOUT ([s] per branch run, 30), FRESH_TIMEOUT ([s] per fresh preparation, 180),
#        FRESH (at most this many accepted values run a fresh preparation, a seeded sample; 0: all),
#        BUILD (build), CSV (docs/data/robustness/settings_property.csv), DOCS (docs).
# Every case is appended to CSV.partial as it ends (a stopped run keeps them). With FRESH=0 about
# an hour on the shared 2-core machine (a fresh preparation of the small damper for every
# accepted value of a key that acts on the preparation, many of the type's extremes running to
# their time limit). In the background:
#   nohup nice -n 19 bash scripts/robustness.sh > robustness.log 2>&1 &
set -euo pipefail
cd "$(dirname "$0")/.."

SEED=${SEED:-48}
DRAWS=${DRAWS:-4}
JOBS=${JOBS:-2}
TIMEOUT=${TIMEOUT:-30}
FRESH_TIMEOUT=${FRESH_TIMEOUT:-180}
FRESH=${FRESH:-0}
BUILD=${BUILD:-build}
CSV=${CSV:-docs/data/robustness/settings_property.csv}
DOCS=${DOCS:-docs}

[ -x "$BUILD/vppdem_tests" ] && [ -x "$BUILD/vppdem" ] || {
  echo "robustness.sh: build first: bash scripts/build.sh vppdem vppdem_tests" >&2
  exit 2
}
mkdir -p "$(dirname "$CSV")"
# Failures are the findings: the test reports them without failing (VPPDEM_PROPERTY_LONG).
VPPDEM_PROPERTY_SEED=$SEED VPPDEM_PROPERTY_DRAWS=$DRAWS VPPDEM_PROPERTY_BRANCHES=0 VPPDEM_PROPERTY_FRESH=$FRESH VPPDEM_PROPERTY_FRESH_TIMEOUT=$FRESH_TIMEOUT \
VPPDEM_PROPERTY_EXTREMES=1 VPPDEM_PROPERTY_JOBS=$JOBS VPPDEM_PROPERTY_TIMEOUT=$TIMEOUT \
VPPDEM_PROPERTY_LONG=1 VPPDEM_PROPERTY_CSV=$PWD/$CSV \
  "$BUILD/vppdem_tests" --gtest_filter=SettingsProperty.EveryValueIsRefusedOrRunsEveryCycleFinite
COMMAND="SEED=$SEED DRAWS=$DRAWS FRESH=$FRESH TIMEOUT=$TIMEOUT FRESH_TIMEOUT=$FRESH_TIMEOUT bash scripts/robustness.sh"
PYTHONPATH=src/python /usr/bin/python3 -m vppdem.report robustness "$CSV" "$DOCS" "$COMMAND" "$(git rev-parse --short HEAD)"
