#!/usr/bin/env bash
# Cost per step of clumps against spheres (issue 24, item 5): the paper's damper (default
# settings, about 1100 grains) prepared with spheres and with each shape asked for, run through
# the vacuum and a short cycle, then the steps of each run.ckpt timed in one run of this script
# (vppdem bench checkpoint), shapes alternating, best of REPS. Prints steps/s per shape and the
# ratio of the time per step to the spheres' (target for dimers: at most 2.2), and the ratio per
# simulated second (the clumps' critical step is smaller).
# usage: bench/grain_shapes.sh [SHAPE ...]   (default: dimer)   env: VPPDEM (build/vppdem),
#        OUT (out/bench_shapes), REPS (3), STEPS (3000), THREADS (1)
set -euo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-build/vppdem}
OUT=${OUT:-out/bench_shapes}
REPS=${REPS:-3}
STEPS=${STEPS:-3000}
THREADS=${THREADS:-1}
shapes=("$@")
[ ${#shapes[@]} -gt 0 ] || shapes=(dimer)
mkdir -p "$OUT"
for s in sphere "${shapes[@]}"; do
  [ -f "$OUT/$s/run.ckpt" ] && [ -f "$OUT/$s/summary.json" ] && continue
  echo "== preparing the damper with grains.shape = $s" >&2
  "$VPPDEM" damper --out "$OUT/$s" --overwrite --no-plot --quiet --set grains.shape="$s" \
    --set process.cycles=1 --set process.amplitude=0.001 --set process.velocity=0.05 --set simulation.threads=2
done
declare -A best dt
for r in $(seq "$REPS"); do
  for s in sphere "${shapes[@]}"; do
    line=$("$VPPDEM" bench checkpoint --state "$OUT/$s/run.ckpt" --steps "$STEPS" --threads "$THREADS" | tail -1)
    sps=$(echo "$line" | sed 's/.*"steps_per_s": \([0-9.e+]*\).*/\1/')
    dt[$s]=$(echo "$line" | sed 's/.*"dt": \([0-9.e+-]*\).*/\1/')
    grains=$(echo "$line" | sed 's/.*"clumps": \([0-9]*\).*/\1/')
    echo "rep $r $s: $sps steps/s (clumps $grains, dt ${dt[$s]} s)" >&2
    if [ -z "${best[$s]:-}" ] || awk "BEGIN{exit !($sps > ${best[$s]})}"; then best[$s]=$sps; fi
  done
done
echo "| grains.shape | steps/s (best of $REPS, $THREADS thread(s)) | dt [s] | time per step / spheres' | time per simulated second / spheres' |"
echo "|---|---|---|---|---|"
for s in sphere "${shapes[@]}"; do
  awk -v s="$s" -v a="${best[$s]}" -v b="${best[sphere]}" -v da="${dt[$s]}" -v db="${dt[sphere]}" \
    'BEGIN{printf "| %s | %.0f | %.4g | %.3f | %.3f |\n", s, a, da, b / a, (b / a) * (db / da)}'
done
