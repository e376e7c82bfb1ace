#!/usr/bin/env bash
# The paper's damper at the paper's four underpressures from one preparation.
# usage: examples/underpressure_series.sh PREPARED.ckpt OUTDIR [VELOCITY [VPPDEM OPTIONS...]]
#   further arguments go to every vppdem damper run (e.g. --set process.cycles=2);
#   VPPDEM=path/to/vppdem picks the binary (default build/vppdem).
set -euo pipefail
cd "$(dirname "$0")/.."
prep=$1; out=$2; v=${3:-0.02}  # [m/s] quasi-static at every dp here (I < 5e-4, docs/studies.md)
vppdem=${VPPDEM:-build/vppdem}
for dp in 0.02e6 0.04e6 0.06e6 0.08e6; do
  "$vppdem" damper --from "$prep" --out "$out/dp_$dp" --overwrite --quiet --set process.velocity=$v \
    --set process.underpressure=$dp "${@:4}"
  echo "== dp = $dp Pa"; cat "$out/dp_$dp/cycles.csv"
  grep -E '"inertial_number"|"run_seconds"' "$out/dp_$dp/summary.json"
done
