#!/usr/bin/env bash
# The README's figure, docs/main_job_loops.png: the main job's loops, drawn by the package's plot
# (vppdem.plot, numpy and matplotlib under Debian's /usr/bin/python3) from the main job's folder.
#   usage: scripts/main_figure.sh [DIR]   (default out/damper: run `bash scripts/main.sh` first)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/damper}
[ -f "$out/forces.csv" ] || { echo "main_figure.sh: no $out/forces.csv: run bash scripts/main.sh first" >&2; exit 2; }
PYTHONPATH=src/python /usr/bin/python3 -m vppdem.plot "$out"
# Through a temporary name: a failed copy leaves the old figure whole.
cp "$out/loops.png" docs/main_job_loops.png.part
mv docs/main_job_loops.png.part docs/main_job_loops.png
echo "wrote docs/main_job_loops.png from $out/loops.png"
