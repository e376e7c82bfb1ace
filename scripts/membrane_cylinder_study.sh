#!/usr/bin/env bash
# A cylinder given as a mesh (issue 47): the study studies/membrane/cylinder.toml (the same damper
# with the lattice foil and with foil.builder = "mesh", 5 seeds each), two runs at a time under
# `nice -n 5`, the finished runs' small records and the tables kept in docs/data/membrane_cylinder/
# by the sweep itself (--publish: put back into OUT first, so a new machine runs only what is
# missing; killed runs continue from their run.ckpt), then the comparison (python3 -m vppdem.report
# membrane_cylinder: Welch's t on the two foils' W, its 95% interval, |difference| against the
# seeds' SD, the equivalence rule of vppdem.report.rules) into docs/data/membrane_cylinder/report.md,
# its comparison and verdict into docs/membrane.md (--page). About 47
# minutes on the shared 2-core machine.
# usage: scripts/membrane_cylinder_study.sh [--publish-only]
# Knobs: VPPDEM (default build/vppdem), OUT (out/membrane_cylinder), JOBS (2), DATA
# (docs/data/membrane_cylinder).
set -euo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-build/vppdem}
OUT=${OUT:-out/membrane_cylinder}
JOBS=${JOBS:-2}
DATA=${DATA:-docs/data/membrane_cylinder}
mode=()
if [ $# -eq 1 ] && [ "$1" = --publish-only ]; then
  mode=(--report-only)
elif [ $# -gt 0 ]; then
  echo "membrane_cylinder_study.sh: unknown argument(s) '$*' (usage: scripts/membrane_cylinder_study.sh [--publish-only])" >&2
  exit 2
fi
[ -x "$VPPDEM" ] || { echo "membrane_cylinder_study.sh: no vppdem binary at $VPPDEM (build it: bash scripts/build.sh vppdem)" >&2; exit 2; }
mkdir -p "$OUT"
failed=0
nice -n 5 "$VPPDEM" sweep studies/membrane/cylinder.toml --out "$OUT" --publish "$DATA" --jobs "$JOBS" --no-plot "${mode[@]}" || failed=1
PYTHONPATH=src/python /usr/bin/python3 -m vppdem.report membrane_cylinder "$DATA" --page docs/membrane.md > "$DATA/report.md.part" && mv -f "$DATA/report.md.part" "$DATA/report.md"
cat "$DATA/report.md"
exit $failed
