#!/usr/bin/env bash
# Re-analyses the paper's studies (the runs scripts/paper_studies.sh published into
# docs/data/paper/) with the current build and writes docs/paper_comparison.md and its figures
# (docs/paper_*.png). Nothing is simulated: each study's finished runs are laid out as a study
# folder (python3 -m vppdem.report paper assemble; cases another study ran are taken from it) and
# `vppdem sweep --report-only` writes its tables (stationary W, means and 95% intervals over the
# seeds, paired differences), which are published into docs/data/paper/report/<study>/.
# Knobs: VPPDEM (default build/vppdem), DATA (default docs/data/paper), DOCS (default docs).
# Seconds; runs with other work on the machine.
set -euo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-build/vppdem}
DATA=${DATA:-docs/data/paper}
DOCS=${DOCS:-docs}
[ -x "$VPPDEM" ] || { echo "paper_report.sh: no vppdem binary at $VPPDEM (build it: bash scripts/build.sh vppdem)" >&2; exit 2; }
PY=/usr/bin/python3
[ -x "$PY" ] || PY=$(command -v python3)
# The report: the package vppdem.report from the source tree (it needs no compiled module).
REPORT=(env PYTHONPATH=src/python "$PY" -m vppdem.report)
source scripts/publish.sh

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
VPPDEM=$VPPDEM "${REPORT[@]}" paper assemble "$DATA" "$tmp" > "$tmp/studies.txt"
while read -r name toml n; do
  [ "$n" -gt 0 ] || continue
  "$VPPDEM" sweep "$toml" --out "$tmp/$name" --report-only --quiet
  mkdir -p "$DATA/report/$name"
  for f in summary.csv summary_cases.csv summary_paired.csv sources.csv; do
    [ -f "$tmp/$name/$f" ] && publish "$tmp/$name/$f" "$DATA/report/$name/$f"
  done
  for f in "$DATA/$name/COMMAND"; do [ -f "$f" ] && publish "$f" "$DATA/report/$name/COMMAND"; done
  echo "paper_report.sh: $name: $n finished runs" >&2
done < "$tmp/studies.txt"
"${REPORT[@]}" paper write "$DATA/report" "$DOCS/paper_comparison.md" "$DOCS" --command "bash scripts/paper_report.sh"
echo "paper_report.sh: wrote $DOCS/paper_comparison.md" >&2
