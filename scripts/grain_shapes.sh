#!/usr/bin/env bash
# The grain-shape study (studies/grains/shapes.toml, docs/grains.md): one command, the records kept
# by the sweep itself. `vppdem sweep --publish DIR` keeps every finished run's small records
# (case.toml, summary.json, cycles.csv, build.json) and the study's tables in
# docs/data/grains/shapes/, and puts them back into OUT first, so a new machine runs only what is
# missing; killed runs continue from their run.ckpt; a folder holding another build's runs is
# refused (one study, one build: docs/studies.md, "Resuming").
# usage: scripts/grain_shapes.sh [--publish-only]   (--publish-only: publish what has finished, run nothing)
# Knobs: VPPDEM (default build/vppdem), OUT (out/grains/shapes), JOBS (runs at once), DATA
# (docs/data/grains/shapes).
set -euo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-build/vppdem}
OUT=${OUT:-out/grains/shapes}
DATA=${DATA:-docs/data/grains/shapes}
mode=()
if [ $# -eq 1 ] && [ "$1" = --publish-only ]; then
  mode=(--report-only)
elif [ $# -gt 0 ]; then
  echo "grain_shapes.sh: unknown argument(s) '$*' (usage: scripts/grain_shapes.sh [--publish-only])" >&2
  exit 2
fi
[ -x "$VPPDEM" ] || { echo "grain_shapes.sh: no vppdem binary at $VPPDEM (build it: bash scripts/build.sh vppdem)" >&2; exit 2; }
mkdir -p "$OUT"
exec "$VPPDEM" sweep studies/grains/shapes.toml --out "$OUT" --publish "$DATA" ${JOBS:+--jobs "$JOBS"} --no-plot "${mode[@]}"
