#!/usr/bin/env bash
# How many cycles the main job's damper needs before W is stationary: the main job's settings
# (the paper's damper, 0.06 MPa, 0.02 m/s) for 8 cycles instead of 4, W per cycle published as
# docs/data/settle_cycles.csv (docs/damper.md, "Stationary loops"). About 11 minutes on 2 threads;
# the same command again resumes a stopped run from its run.ckpt (or rewrites a finished one's
# records).
# Knobs: VPPDEM (default build/vppdem), OUT (default out/settle), DOCS (default docs),
#        CYCLES (default 8).
set -euo pipefail
cd "$(dirname "$0")/.."

VPPDEM=${VPPDEM:-build/vppdem}
OUT=${OUT:-out/settle}
DOCS=${DOCS:-docs}
CYCLES=${CYCLES:-8}
[ -x "$VPPDEM" ] || { echo "settle_cycles.sh: no vppdem binary at $VPPDEM (build it: bash scripts/build.sh)" >&2; exit 2; }
source scripts/publish.sh
whole_knobs settle_cycles.sh CYCLES

cmd="$VPPDEM damper --out $OUT --no-plot --quiet --set process.velocity=0.02 --set process.cycles=$CYCLES"
$cmd
mkdir -p "$DOCS/data"
publish "$OUT/cycles.csv" "$DOCS/data/settle_cycles.csv"
record "data/settle_cycles.csv" "$cmd"
