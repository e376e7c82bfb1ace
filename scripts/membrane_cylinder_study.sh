#!/usr/bin/env bash
# A cylinder given as a mesh (issue 47): the study studies/membrane/cylinder.toml (the same damper
# with the lattice foil and with foil.builder = "mesh", 5 seeds each) with one vppdem binary, two
# runs at a time under `nice -n 5`, then the comparison (python3 -m vppdem.report membrane_cylinder: Welch's
# t on the two foils' W, its 95% interval, |difference| against the seeds' SD). The small records
# of every finished run (case.toml, cycles.csv, summary.json; never vtk/ or checkpoints) are kept
# in docs/data/membrane_cylinder/<case>/ with the study's summary.csv and COMMAND, and the report
# goes to docs/data/membrane_cylinder/report.md (quoted in docs/membrane.md, "A cylinder given as
# a mesh"). About 47 minutes on the shared 2-core machine (10 runs of 6-10 minutes, two at a
# time; about 3.5 CPU minutes each); a stopped study resumes (finished cases are kept, killed runs
# continue from their run.ckpt).
# usage: scripts/membrane_cylinder_study.sh [--publish-only]
# Knobs: VPPDEM (default build/vppdem), OUT (out/membrane_cylinder), JOBS (2), DATA
# (docs/data/membrane_cylinder).
set -euo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-build/vppdem}
OUT=${OUT:-out/membrane_cylinder}
JOBS=${JOBS:-2}
DATA=${DATA:-docs/data/membrane_cylinder}
publish_only=0
if [ $# -eq 1 ] && [ "$1" = --publish-only ]; then
  publish_only=1
elif [ $# -gt 0 ]; then
  echo "membrane_cylinder_study.sh: unknown argument(s) '$*' (usage: scripts/membrane_cylinder_study.sh [--publish-only])" >&2
  exit 2
fi
source scripts/publish.sh
whole_knobs membrane_cylinder_study.sh JOBS
mkdir -p "$OUT" "$DATA"
restore_records "$DATA" "$OUT"
failed=0
if [ $publish_only -eq 0 ]; then
  [ -x "$VPPDEM" ] || { echo "membrane_cylinder_study.sh: no vppdem binary at $VPPDEM (build it: bash scripts/build.sh vppdem)" >&2; exit 2; }
  commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
  cmd=(nice -n 5 "$VPPDEM" sweep studies/membrane/cylinder.toml --out "$OUT" --jobs "$JOBS" --no-plot)
  printf '%s (commit %s)\n' "${cmd[*]}" "$commit" > "$OUT/COMMAND"
  "${cmd[@]}" || failed=1
fi
save_records "$OUT" "$DATA"
PYTHONPATH=src/python /usr/bin/python3 -m vppdem.report membrane_cylinder "$DATA" > "$DATA/report.md.part" && mv -f "$DATA/report.md.part" "$DATA/report.md"
cat "$DATA/report.md"
echo "membrane_cylinder_study.sh: $SAVED finished runs in $DATA"
exit $failed
