#!/usr/bin/env bash
# Runs the grain-shape study (studies/grains/shapes.toml) with one pinned vppdem binary and keeps
# every finished run's small records in the repository (docs/data/grains/shapes/<case>/:
# case.toml, summary.json, cycles.csv; the study's summary.csv). They are published when the
# sweep returns, or at any time with --publish-only (run it before a session ends: the runs
# finished by then are kept, a new machine loses at most those in flight). A binary of another
# pinned build than the published runs' (their COMMAND) is refused: one study, one build.
# usage: scripts/grain_shapes.sh [--publish-only]
# Knobs: VPPDEM (default pinned/vppdem), OUT (out/grains/shapes), JOBS (runs at once), DATA
# (docs/data/grains/shapes). Resumable like scripts/paper_studies.sh: published records go back
# into OUT first (a case with summary.json is done), killed runs continue from their run.ckpt.
set -euo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-pinned/vppdem}
OUT=${OUT:-out/grains/shapes}
JOBS=${JOBS:-}
DATA=${DATA:-docs/data/grains/shapes}
publish_only=0
if [ $# -eq 1 ] && [ "$1" = --publish-only ]; then
  publish_only=1
elif [ $# -gt 0 ]; then
  echo "grain_shapes.sh: unknown argument(s) '$*' (usage: scripts/grain_shapes.sh [--publish-only])" >&2
  exit 2
fi
source scripts/publish.sh
mkdir -p "$OUT" "$DATA"
# Published records back into the run folders.
restore_records "$DATA" "$OUT"
failed=0
if [ $publish_only -eq 0 ]; then
  [ -x "$VPPDEM" ] || { echo "grain_shapes.sh: no vppdem binary at $VPPDEM" >&2; exit 2; }
  commit=$(cat "$(dirname "$VPPDEM")/COMMIT" 2>/dev/null || echo unknown)
  check_pinned "$commit" grain_shapes.sh "$DATA" "$OUT"
  [ -z "$JOBS" ] || whole_knobs grain_shapes.sh JOBS
  cmd=("$VPPDEM" sweep studies/grains/shapes.toml --out "$OUT" ${JOBS:+--jobs "$JOBS"} --no-plot)
  printf '%s (pinned build %s)\n' "${cmd[*]}" "$commit" > "$OUT/COMMAND"
  "${cmd[@]}" || failed=1
fi
save_records "$OUT" "$DATA"
echo "grain_shapes.sh: $SAVED finished runs in $DATA"
exit $failed
