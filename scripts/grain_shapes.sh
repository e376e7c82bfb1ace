#!/usr/bin/env bash
# Runs the grain-shape study (studies/grains/shapes.toml) with one pinned vppdem binary and keeps
# every finished run's small records in the repository (docs/data/grains/shapes/<case>/:
# case.toml, summary.json, cycles.csv; the study's summary.csv), so a new machine loses at most
# the runs in flight.
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
[ "${1:-}" = "--publish-only" ] && publish_only=1
source scripts/publish.sh
mkdir -p "$OUT" "$DATA"
# Published records back into the run folders.
for d in "$DATA"/*/; do
  [ -f "$d/summary.json" ] || continue
  c=$(basename "$d")
  [ -f "$OUT/$c/summary.json" ] && continue
  mkdir -p "$OUT/$c"
  for f in case.toml cycles.csv summary.json; do [ -f "$d/$f" ] && publish "$d/$f" "$OUT/$c/$f"; done
done
failed=0
if [ $publish_only -eq 0 ]; then
  [ -x "$VPPDEM" ] || { echo "grain_shapes.sh: no vppdem binary at $VPPDEM" >&2; exit 2; }
  cmd="$VPPDEM sweep studies/grains/shapes.toml --out $OUT ${JOBS:+--jobs $JOBS} --no-plot"
  printf '%s (pinned build %s)\n' "$cmd" "$(cat "$(dirname "$VPPDEM")/COMMIT" 2>/dev/null || echo unknown)" > "$OUT/COMMAND"
  $cmd || failed=1
fi
n=0
for d in "$OUT"/*/; do
  [ -f "$d/summary.json" ] || continue
  c=$(basename "$d")
  mkdir -p "$DATA/$c"
  for f in case.toml cycles.csv summary.json; do
    [ -f "$d/$f" ] && ! cmp -s "$d/$f" "$DATA/$c/$f" && publish "$d/$f" "$DATA/$c/$f"
  done
  n=$((n + 1))
done
for f in summary.csv summary_cases.csv COMMAND; do [ -f "$OUT/$f" ] && publish "$OUT/$f" "$DATA/$f"; done
echo "grain_shapes.sh: $n finished runs in $DATA"
exit $failed
