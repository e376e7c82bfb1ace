#!/usr/bin/env bash
# The time step decided by intervals (issue 60, item 2): studies/paper/timestep_045.toml (leg 1,
# dt_safety 0.45, each seed preparing its sample) and timestep_stationary.toml (leg 2, 0.3 and
# 0.15 from leg 1's sample of the seed), run seed by seed so that every finished seed is a
# complete pair: leg 1 with --seeds K, then leg 2 with --seeds K, K = 1 .. the planned 10. Each
# sweep publishes its finished cases' records into docs/data/paper/<leg>/ as they end.
# Resumable: the same command again continues (finished cases count as finished, a killed case
# continues from its run.ckpt). In the background:
#   nohup nice -n 19 bash scripts/timestep_study.sh > timestep.log 2>&1 &
#   VPPDEM  the pinned binary (default pinned/ts/vppdem; docs/data/SOURCES.md names its commit)
#   OUT     run folders (default out/paper)   JOBS  leg 2's runs at once (default 1)
#   SEEDS   the last seed (default 10, the plan's)
set -euo pipefail
cd "$(dirname "$0")/.."
VPPDEM=${VPPDEM:-pinned/ts/vppdem}
OUT=${OUT:-out/paper}
JOBS=${JOBS:-1}
SEEDS=${SEEDS:-10}
[ -x "$VPPDEM" ] || { echo "timestep_study.sh: no vppdem binary at $VPPDEM (pin one: mkdir -p pinned/ts && cp build/vppdem pinned/ts/)" >&2; exit 2; }
for k in $(seq 1 "$SEEDS"); do
  for leg in timestep_045 timestep_stationary; do
    jobs=1
    [ $leg = timestep_045 ] || jobs=$JOBS
    echo "== seed $k, $leg ($(date -u +%FT%TZ))"
    "$VPPDEM" sweep "studies/paper/$leg.toml" --out "$OUT/$leg" --seeds "$k" --jobs "$jobs" \
      --publish "docs/data/paper/$leg" --no-plot --quiet
  done
done
