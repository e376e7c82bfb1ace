#!/usr/bin/env bash
# The README's first command: install, build, run the main job.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
out=${1:-out/example}
build/vppdem scene examples/01_pour_into_cylinder.toml --out "$out" --overwrite
echo "main job done: outputs in $out (tracked.csv, walls.csv, summary.json, vtk/ for ParaView)"
