#!/usr/bin/env bash
# The damper at its working frequencies with the air inside (issue 23; docs/operation.md):
# examples/operation/pump.toml (a 2 m^3/h pump, triangle and sine, 1-20 Hz, 3 seeds), its
# constant-model twin constant.toml (1, 5, 10, 20 Hz: where the pump may fall behind, and one where
# it should not),
# then python3 -m vppdem.report operation: docs/operation.md's tables and figures from the records, which
# are kept in docs/data/operation/ (case.toml, summary.json, cycles.csv of every run; the last
# cycle of forces.csv for seed 1 at 10 and 20 Hz).
#
# usage: bash examples/operation/run.sh [--report-only]
#   --report-only: run nothing; the report from docs/data/operation.
# Knobs (environment variables):
#   VPPDEM   the binary (default build/vppdem: bash scripts/build.sh vppdem)
#   OUT      run folders (default out/operation)
#   JOBS     runs at once (default: vppdem's choice, the free cores)
#   SAMPLES  a folder with prepared samples s1.ckpt s2.ckpt s3.ckpt (prepared.ckpt of the paper's
#            damper at the defaults, seeds 1-3) to branch from instead of preparing them; without
#            it the pump study prepares them and the constant study branches from those
# Both studies resume where they stopped (re-run the same command). About 15 minutes of one core
# per seed and waveform at 1-20 Hz with the pump, 10 more for the twins: about 75 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/../.."
VPPDEM=${VPPDEM:-build/vppdem}
OUT=${OUT:-out/operation}
JOBS=${JOBS:-}
SAMPLES=${SAMPLES:-}
DATA=docs/data/operation
PY=/usr/bin/python3
[ -x "$PY" ] || PY=$(command -v python3)
report_only=0
[ "${1:-}" = "--report-only" ] && report_only=1
source scripts/publish.sh

if [ $report_only -eq 0 ]; then
  [ -x "$VPPDEM" ] || { echo "run.sh: no vppdem binary at $VPPDEM (build it: bash scripts/build.sh vppdem)" >&2; exit 2; }
  [ -z "$JOBS" ] || [[ $JOBS =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: JOBS = '$JOBS': must be an integer >= 1" >&2; exit 2; }
  jobs_arg=${JOBS:+--jobs $JOBS}
  commit=$(cat "$(dirname "$VPPDEM")/COMMIT" 2>/dev/null || git rev-parse --short HEAD)

  # branch STUDY DIR: every case of the study that has neither records nor a checkpoint starts
  # from its seed's sample in $SAMPLES (the sweep resumes a case from DIR/<case>/run.ckpt; a
  # prepared sample carries no settings, so the case's apply).
  branch() {
    local toml=$1 dir=$2 name seed
    [ -n "$SAMPLES" ] || return 0
    "$VPPDEM" sweep "$toml" --out "$dir" --list | awk '{print $4}' | while read -r name; do
      seed=${name##*simulation.seed=}
      [ -f "$dir/$name/summary.json" ] || [ -f "$dir/$name/run.ckpt" ] || [ ! -f "$SAMPLES/s$seed.ckpt" ] && continue
      mkdir -p "$dir/$name"
      cp "$SAMPLES/s$seed.ckpt" "$dir/$name/run.ckpt.tmp" && mv "$dir/$name/run.ckpt.tmp" "$dir/$name/run.ckpt"
    done
  }
  for study in pump constant; do
    toml=examples/operation/$study.toml
    if [ $study = constant ] && [ -z "$SAMPLES" ]; then
      # The pump study's samples: its first case of each seed prepared one.
      SAMPLES=$OUT/samples
      mkdir -p "$SAMPLES"
      for seed in 1 2 3; do
        p=$(ls "$OUT"/pump/*_simulation.seed=$seed/prepared.ckpt 2>/dev/null | head -1 || true)
        [ -n "$p" ] && ln -sf "$(realpath "$p")" "$SAMPLES/s$seed.ckpt"
      done
    fi
    mkdir -p "$OUT/$study"
    branch "$toml" "$OUT/$study"
    cmd="$VPPDEM sweep $toml --out $OUT/$study $jobs_arg --no-plot"
    echo "== $cmd"
    printf '%s (build %s)\n' "$cmd" "$commit" > "$OUT/$study/COMMAND"
    $cmd
    # Publish the small records.
    for d in "$OUT/$study"/*/; do
      [ -f "$d/summary.json" ] || continue
      c=$(basename "$d")
      mkdir -p "$DATA/$study/$c"
      for f in case.toml cycles.csv summary.json; do publish "$d/$f" "$DATA/$study/$c/$f"; done
      # The last cycle of seed 1's fast runs: the loops' shape at the onset of compression.
      if [[ $c == *frequency=1[0]_*seed=1 || $c == *frequency=20_*seed=1 ]]; then
        awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "cycle") k = i; print; next }
                 { last[NR] = $0; cyc[NR] = $k; if ($k > m) m = $k }
                 END { for (i = 2; i <= NR; i++) if (cyc[i] == m) print last[i] }' "$d/forces.csv" > "$d/forces_last_cycle.csv"
        publish "$d/forces_last_cycle.csv" "$DATA/$study/$c/forces_last_cycle.csv"
      fi
    done
    publish "$OUT/$study/COMMAND" "$DATA/$study/COMMAND"
  done
fi
PYTHONPATH=src/python "$PY" -m vppdem.report operation "$DATA" docs
