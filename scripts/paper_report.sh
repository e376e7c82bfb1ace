#!/usr/bin/env bash
# Re-analyses the paper's studies (the runs scripts/paper_studies.sh published into
# docs/data/paper/) with the current build and writes docs/paper_comparison.md and its figures
# (docs/paper_*.png). Nothing is simulated: each study's finished runs are laid out as a study
# folder (python3 -m vppdem.report paper assemble; cases another study ran are taken from it) and
# `vppdem sweep --report-only --publish` writes its tables (stationary W, means and 95% intervals
# over the seeds, paired differences) and publishes them, with the assembly's sources.csv and the
# study's COMMAND, into docs/data/paper/report/<study>/ (the assembled runs' records stay where
# they came from: they have no case.toml).
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

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
VPPDEM=$VPPDEM "${REPORT[@]}" paper assemble "$DATA" "$tmp" > "$tmp/studies.txt"
while read -r name toml n; do
  [ "$n" -gt 0 ] || continue
  # The study's COMMAND is part of the assembly (the published study's, which the sweep publishes).
  [ ! -f "$DATA/$name/COMMAND" ] || cp "$DATA/$name/COMMAND" "$tmp/$name/COMMAND"
  "$VPPDEM" sweep "$toml" --out "$tmp/$name" --report-only --publish "$DATA/report/$name" --quiet
  echo "paper_report.sh: $name: $n finished runs" >&2
done < "$tmp/studies.txt"
"${REPORT[@]}" paper write "$DATA/report" "$DOCS/paper_comparison.md" "$DOCS" --command "bash scripts/paper_report.sh"
echo "paper_report.sh: wrote $DOCS/paper_comparison.md" >&2
