#!/usr/bin/env bash
# The time step decided by intervals (issue 60, item 2): studies/paper/timestep_045.toml (leg 1,
# dt_safety 0.45, each seed preparing its sample) and timestep_stationary.toml (leg 2, 0.3 and
# 0.15 from the seed's sample at 0.45), run seed by seed so that every finished seed is a complete
# triple: leg 1 with --seeds K, then leg 2 with --seeds K, K = 1 .. the planned 10. Each sweep
# publishes its finished cases' records into docs/data/paper/<leg>/ as they end; a seed whose
# three runs are published is skipped. Leg 2 takes leg 1's sample of the seed while its run
# folder holds it; on a new machine (the folders do not outlive a session, the published records
# keep no checkpoint) timestep_samples.toml prepares the same sample again first.
# Resumable within a session: the same command again continues (a killed case from its run.ckpt).
# In the background:
#   nohup nice -n 19 bash scripts/timestep_study.sh > timestep.log 2>&1 &
#   VPPDEM  the pinned binary (default pinned/ts/vppdem; docs/data/SOURCES.md names its commit)
#   OUT     run folders (default out/paper)   JOBS  leg 2's runs at once (default 1)
#   SEEDS   the seeds to run (default "1 2 ... 10", the plan's)
set -euo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-pinned/ts/vppdem}
OUT=${OUT:-out/paper}
JOBS=${JOBS:-1}
SEEDS=${SEEDS:-$(seq -s ' ' 1 10)}
DATA=docs/data/paper
[ -x "$VPPDEM" ] || { echo "timestep_study.sh: no vppdem binary at $VPPDEM (pin one: mkdir -p pinned/ts && cp build/vppdem pinned/ts/)" >&2; exit 2; }
sweep() {  # LEG SEED JOBS [--publish]
  local leg=$1 k=$2 jobs=$3; shift 3
  echo "== seed $k, $leg ($(date -u +%FT%TZ))"
  mkdir -p "$OUT/$leg"
  "$VPPDEM" sweep "studies/paper/$leg.toml" --out "$OUT/$leg" --seeds "$k" --jobs "$jobs" "$@" --no-plot --quiet
}
mkdir -p "$OUT/timestep_045" "$OUT/timestep_samples"  # leg 2 names both as its samples_from
for k in $SEEDS; do
  done_runs=0
  for f in "$DATA/timestep_045/simulation.seed=$k" "$DATA/timestep_stationary/simulation.dt-safety=0.3_simulation.seed=$k" \
           "$DATA/timestep_stationary/simulation.dt-safety=0.15_simulation.seed=$k"; do
    [ -f "$f/summary.json" ] && done_runs=$((done_runs + 1))
  done
  [ $done_runs -lt 3 ] || { echo "== seed $k: its three runs are published"; continue; }
  sweep timestep_045 "$k" 1 --publish "$DATA/timestep_045"
  [ -f "$OUT/timestep_045/simulation.seed=$k/prepared.ckpt" ] || sweep timestep_samples "$k" 1
  sweep timestep_stationary "$k" "$JOBS" --publish "$DATA/timestep_stationary"
done
