#!/usr/bin/env bash
# Reruns the studies of issue 12 ("Studies you can trust": ensembles of seeds, stationary loops,
# paired velocity convergence, a calibration that could fail) into $OUT and regenerates
# docs/data/*.csv and the study figures in docs/; every figure carries the command that made it
# (a caption), and docs/data/SOURCES.md lists the command behind every file.
#
# usage: scripts/trust_studies.sh [STUDY ...]
#   STUDY: underpressure friction young radius damping velocity paper_velocity calibration
#          (default: all, in this order; calibration uses the friction study's runs, paper_velocity
#          the velocity study's seed-1 sample)
# Knobs (environment variables):
#   VPPDEM    the vppdem binary (default build/vppdem: build it first, scripts/build.sh)
#   OUT       output root (default out/trust)
#   SEEDS     realisations per case (default 3)
#   CYCLES    cycles per run (default 5; W can settle from cycle 3 on, docs/damper.md)
#   VELOCITY  loading velocity [m/s] of every study but the velocity study (default 0.01: W within
#             the paired interval of slower loading there, docs/studies.md "Velocity convergence: results")
#   JOBS      runs at once (default: vppdem's choice, the free cores)
#   DOCS      where figures and data go (default docs)
#   SETS      further overrides for every run, e.g. SETS="--set simulation.dt_safety=0.4" (default none;
#             the tests run this script on the small damper this way)
# Resumable: the same command again continues where it stopped (finished runs are kept, killed
# ones resume from their checkpoints). Changing SEEDS, CYCLES or VELOCITY needs another OUT.
# It runs for days on a 2-core machine (docs/studies.md, "Regenerating the studies"); in the
# background:
#   nohup nice -n 19 bash scripts/trust_studies.sh > trust.log 2>&1 &
set -euo pipefail
cd "$(dirname "$0")/.."

VPPDEM=${VPPDEM:-build/vppdem}
OUT=${OUT:-out/trust}
SEEDS=${SEEDS:-3}
CYCLES=${CYCLES:-5}
VELOCITY=${VELOCITY:-0.01}
JOBS=${JOBS:-}
DOCS=${DOCS:-docs}
SETS=${SETS:-}
PY=/usr/bin/python3  # Debian's, with matplotlib and numpy
# The figures: the package's vppdem.plot from the source tree (it needs no compiled module).
PLOT="env PYTHONPATH=src/python $PY -m vppdem.plot"
# The reports: the package's vppdem.report, likewise.
REPORT="env PYTHONPATH=src/python $PY -m vppdem.report"

[ -x "$VPPDEM" ] || { echo "trust_studies.sh: no vppdem binary at $VPPDEM (build it: bash scripts/build.sh)" >&2; exit 2; }
# publish FILE DEST, record FILES COMMAND, whole_knobs WHO NAME...
source scripts/publish.sh
whole_knobs trust_studies.sh SEEDS CYCLES
[[ $VELOCITY =~ ^[0-9.eE+-]+$ ]] || { echo "trust_studies.sh: VELOCITY = '$VELOCITY': must be a velocity in m/s" >&2; exit 2; }
[ -z "$JOBS" ] || whole_knobs trust_studies.sh JOBS
jobs_arg=${JOBS:+--jobs $JOBS}
mkdir -p "$OUT" "$DOCS/data"
studies=("$@")
all=(underpressure friction young radius damping velocity paper_velocity calibration)
[ ${#studies[@]} -gt 0 ] || studies=("${all[@]}")
for s in "${studies[@]}"; do  # every name checked before anything runs
  [[ " ${all[*]} " == *" $s "* ]] || { echo "trust_studies.sh: unknown study '$s' (studies: ${all[*]})" >&2; exit 2; }
done
failed=0

# sweep NAME STUDY_FILE FIGURE_PREFIX [--set ...]: runs the study with the knobs, then publishes
# its summaries and figures.
sweep() {
  local name=$1 file=$2 prefix=$3
  shift 3
  local cmd="$VPPDEM sweep $file --out $OUT/$name --seeds $SEEDS --set process.cycles=$CYCLES $SETS $* $jobs_arg --no-plot"
  echo "== $name: $cmd"
  if ! $cmd; then
    echo "trust_studies.sh: $name: some runs failed (their rows in $OUT/$name/summary.csv say why)" >&2
    failed=1
  fi
  $PLOT "$OUT/$name" --kind sweep --prefix "$prefix" --caption "$cmd"
  publish "$OUT/$name/${prefix}_W.png" "$DOCS/${prefix}_W.png"
  publish "$OUT/$name/${prefix}_loops.png" "$DOCS/${prefix}_loops.png"
  publish "$OUT/$name/summary.csv" "$DOCS/data/${prefix}_summary.csv"
  publish "$OUT/$name/summary_cases.csv" "$DOCS/data/${prefix}_cases.csv"
  record "${prefix}_W.png, ${prefix}_loops.png, data/${prefix}_summary.csv, data/${prefix}_cases.csv" "$cmd"
}

velocity_set="--set process.velocity=$VELOCITY"
for s in "${studies[@]}"; do
  case $s in
    underpressure) sweep underpressure examples/study_underpressure.toml study_underpressure $velocity_set ;;
    friction) sweep friction examples/study_friction.toml study_friction $velocity_set ;;
    young) sweep young examples/study_young.toml study_young $velocity_set ;;
    radius) sweep radius examples/study_radius_underpressure.toml study_radius $velocity_set ;;
    damping) sweep damping examples/study_energy_split.toml study_damping $velocity_set ;;
    velocity)
      sweep velocity examples/study_velocity.toml study_velocity
      cmd="$REPORT paired_velocity $OUT/velocity --out $OUT/velocity/study_velocity_paired"
      echo "== velocity, paired: $cmd"
      $cmd --caption "$cmd"
      publish "$OUT/velocity/study_velocity_paired.csv" "$DOCS/data/study_velocity_paired.csv"
      publish "$OUT/velocity/study_velocity_paired.png" "$DOCS/study_velocity_paired.png"
      record "study_velocity_paired.png, data/study_velocity_paired.csv" "$cmd"
      ;;
    paper_velocity)
      # One cycle at the paper's 3.33e-4 m/s, 0.06 MPa, from the velocity study's seed-1 sample:
      # compared with that seed's first cycles at the study's velocities (same sample, paired).
      ckpt=$(ls "$OUT"/velocity/*simulation.seed=1/prepared.ckpt 2>/dev/null | head -1 || true)
      [ -n "$ckpt" ] || { echo "trust_studies.sh: paper_velocity needs the velocity study's seed-1 sample: run 'velocity' first" >&2; exit 2; }
      d="$OUT/paper_velocity"
      cmd="$VPPDEM damper --from $ckpt --out $d --set process.velocity=3.33e-4 --set process.cycles=1 --set process.underpressure=0.06e6 --set output.energy=false $SETS --no-plot"
      echo "== paper_velocity: $cmd"
      if [ -f "$d/summary.json" ]; then echo "   done earlier"
      elif [ -f "$d/run.ckpt" ]; then $VPPDEM damper --from "$d/run.ckpt" --out "$d" --no-plot
      else $cmd; fi
      $PY - "$OUT/velocity" "$d" "$DOCS/data/paper_velocity_cycle1.csv" <<'EOF'
import csv, os, sys
study, paper, out = sys.argv[1:4]
rows = []
for r in csv.DictReader(open(os.path.join(study, "summary.csv"))):
    if r["status"] == "ok" and r["simulation.seed"] == "1" and float(r["process.underpressure"]) == 0.06e6:
        c = next(csv.DictReader(open(os.path.join(study, r["case"], "cycles.csv"))))
        rows.append((float(r["process.velocity"]), c["W"], c["peak_force"], r["case"]))
c = next(csv.DictReader(open(os.path.join(paper, "cycles.csv"))))
rows.append((3.33e-4, c["W"], c["peak_force"], os.path.basename(paper)))
with open(out + ".part", "w") as f:
    f.write("velocity,W_cycle1,peak_force_cycle1,run\n")
    for v, w, p, name in sorted(rows):
        f.write(f"{v:g},{w},{p},{name}\n")
os.replace(out + ".part", out)
print(f"wrote {out}")
EOF
      record "data/paper_velocity_cycle1.csv" "$cmd"
      ;;
    calibration)
      # A calibration that could fail, at the paper's geometry: the "experiment" is a run at
      # mu = 0.45 (between the grid values) from a seed the study does not run, written as a rig
      # would, with noise; the grid is the friction study's (same folder: no run is repeated).
      t="$OUT/calibration_truth"
      tcmd="$VPPDEM damper --out $t --set grains.friction=0.45 --set simulation.seed=101 --set process.underpressure=0.06e6 --set process.velocity=$VELOCITY --set process.cycles=$CYCLES --set output.energy=false $SETS --no-plot"
      echo "== calibration, synthetic experiment: $tcmd"
      if [ -f "$t/summary.json" ]; then echo "   done earlier"
      elif [ -f "$t/run.ckpt" ]; then $VPPDEM damper --from "$t/run.ckpt" --out "$t" --no-plot
      else $tcmd; fi
      $PY tools/synthetic_experiment.py "$t/forces.csv" "$t/experiment.csv"
      cmd="$VPPDEM calibrate examples/study_friction.toml --experiment $t/experiment.csv --out $OUT/friction --seeds $SEEDS --set process.cycles=$CYCLES $SETS $velocity_set $jobs_arg --time-column t_s --displacement-column stroke_mm --force-column load_kN --displacement-unit mm --force-unit kN --compression-negative"
      echo "== calibration: $cmd"
      if ! $cmd; then
        echo "trust_studies.sh: calibration failed (see $OUT/friction/calibration_failed.json)" >&2
        failed=1
      else
        $PLOT "$OUT/friction" --kind calibration --caption "$tcmd; tools/synthetic_experiment.py; $cmd"
        publish "$OUT/friction/calibration.png" "$DOCS/calibration_synthetic.png"
        publish "$OUT/friction/calibration.json" "$DOCS/data/calibration_synthetic.json"
        publish "$OUT/friction/misfit.csv" "$DOCS/data/calibration_synthetic_misfit.csv"
        publish "$OUT/friction/misfit_runs.csv" "$DOCS/data/calibration_synthetic_misfit_runs.csv"
        record "calibration_synthetic.png, data/calibration_synthetic*.csv, data/calibration_synthetic.json" "$tcmd; $PY tools/synthetic_experiment.py $t/forces.csv $t/experiment.csv; $cmd"
      fi
      ;;
  esac
done
if [ $failed -eq 0 ]; then echo "trust_studies.sh: done"; else echo "trust_studies.sh: done, with failures (see above)"; fi
exit $failed
