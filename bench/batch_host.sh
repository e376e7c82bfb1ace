#!/usr/bin/env bash
# The batch engine's host backend against World's own step (issue 22, docs/gpu.md): the paper's
# damper during cycling (a run.ckpt; prepared as bench/grain_shapes.sh prepares its spheres when
# STATE is not given), its steps timed in one run of this script by vppdem bench checkpoint:
# World (SIMD kernels, 1 thread), a batch of 1 copy (1 thread), a batch of 2 copies (2 threads),
# alternating, best of REPS. Prints steps/s and system-steps/s and their ratios to World's. The
# host backend runs the kernel bodies one index at a time (scalar code, the GPU's bodies): it is
# the GPU's test bed, not a faster CPU path.
# usage: bench/batch_host.sh    env: VPPDEM (build/vppdem), STATE (out/bench_shapes/sphere/run.ckpt),
#        REPS (3), STEPS (3000)
set -euo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-build/vppdem}
STATE=${STATE:-out/bench_shapes/sphere/run.ckpt}
REPS=${REPS:-3}
STEPS=${STEPS:-3000}
if [ ! -f "$STATE" ]; then
  dir=$(dirname "$STATE")
  echo "== preparing the damper into $dir" >&2
  "$VPPDEM" damper --out "$dir" --overwrite --no-plot --quiet \
    --set process.cycles=1 --set process.amplitude=0.001 --set process.velocity=0.05 --set simulation.threads=2
fi
declare -A best
runs=("world|--threads 1" "batch1|--threads 1 --batch 1" "batch2|--threads 2 --batch 2")
for r in $(seq "$REPS"); do
  for run in "${runs[@]}"; do
    name=${run%%|*}
    # shellcheck disable=SC2086
    line=$("$VPPDEM" bench checkpoint --state "$STATE" --steps "$STEPS" ${run#*|} | tail -1)
    if [[ $line == *system_steps_per_s* ]]; then
      sps=$(echo "$line" | sed 's/.*"system_steps_per_s": \([0-9.e+]*\).*/\1/')
    else
      sps=$(echo "$line" | sed 's/.*"steps_per_s": \([0-9.e+]*\).*/\1/')
    fi
    echo "rep $r $name: $sps system-steps/s" >&2
    if [ -z "${best[$name]:-}" ] || awk "BEGIN{exit !($sps > ${best[$name]})}"; then best[$name]=$sps; fi
  done
done
echo "| run | system-steps/s (best of $REPS) | / World's |"
echo "|---|---|---|"
for run in "${runs[@]}"; do
  name=${run%%|*}
  awk -v n="$name" -v a="${best[$name]}" -v w="${best[world]}" 'BEGIN{printf "| %s | %.0f | %.3f |\n", n, a, a / w}'
done
