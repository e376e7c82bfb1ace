#!/usr/bin/env bash
# Reruns the studies of issue 12 ("Studies you can trust": ensembles of seeds, stationary loops,
# paired velocity convergence, a calibration that could fail) into $OUT and regenerates
# docs/data/*.csv and the study figures in docs/; every figure carries the command that made it
# (a caption), and docs/data/SOURCES.md lists the command behind every file. Each part is one
# study file of studies/trust/ run by one `vppdem sweep` into $OUT/PART (docs/studies.md,
# "Regenerating the studies"), then its figures and tables:
#   underpressure, friction, young, radius, damping   studies/trust/PART.toml: the paper's damper at
#               VELOCITY, CYCLES cycles, SEEDS seeds; figures by vppdem.plot, published as
#               $DOCS/study_PART_{W,loops}.png and $DOCS/data/study_PART_{summary,cases}.csv
#               (damping: friction x local damping)
#   velocity    studies/trust/velocity.toml (dp 0.02 / 0.06 MPa x 0.1 ... 0.005 m/s; VELOCITY does
#               not apply), published likewise, then paired against the slowest velocity
#               (python3 -m vppdem.report paired_velocity: $DOCS/study_velocity_paired.png, .csv)
#   paper_velocity  studies/trust/paper_velocity.toml: one cycle at the paper's 3.33e-4 m/s, 0.06 MPa,
#               seed 1; it prepares nothing: its case branches from the seed's sample in the sibling
#               folder $OUT/velocity (samples_from, matched by geometry; summary.json "from" names
#               it), so run 'velocity' first; then python3 -m vppdem.report paper_velocity_cycle1
#               tabulates that seed's cycle 1 at every velocity, published as
#               $DOCS/data/paper_velocity_cycle1.csv
#   calibration studies/trust/calibration_truth.toml (one run: friction 0.45, seed 101, the
#               friction study's conditions) into $OUT/calibration_truth, tools/synthetic_experiment.py
#               writes its loop as a rig would, and `vppdem calibrate studies/trust/friction.toml`
#               into $OUT/friction (the friction study's runs: the same --seeds and --set) must
#               recover 0.45: $DOCS/calibration_synthetic.png, $DOCS/data/calibration_synthetic*
# Every study file sets simulation.dt_safety = 0.45, the step of the published results (0.3 is
# the default now); SETS may override it.
#
# usage: scripts/trust_studies.sh [STUDY ...]
#   STUDY: underpressure friction young radius damping velocity paper_velocity calibration
#          (default: all, in this order; calibration uses the friction study's runs, paper_velocity
#          the velocity study's seed-1 sample)
# Knobs (environment variables), passed to the sweeps as --seeds and --set (the study files hold
# the defaults):
#   VPPDEM    the vppdem binary (default build/vppdem: build it first, scripts/build.sh)
#   OUT       output root (default out/trust)
#   SEEDS     realisations per case (default 3; --seeds: not for paper_velocity, seed 1, nor the
#             calibration's single run, seed 101)
#   CYCLES    cycles per run (default 5, --set process.cycles; W can settle from cycle 3 on,
#             docs/damper.md; not for paper_velocity, one cycle)
#   VELOCITY  loading velocity [m/s] of every study but velocity and paper_velocity (default 0.01,
#             --set process.velocity: W within the paired interval of slower loading there,
#             docs/studies.md "Velocity convergence: results")
#   JOBS      runs at once (--jobs; default: vppdem's choice, the free cores)
#   DOCS      where figures and data go (default docs)
#   SETS      further overrides for every run, e.g. SETS="--set simulation.dt_safety=0.4" (default none;
#             the tests run this script on the small damper this way)
# Resumable: the same command again continues where it stopped (finished runs are kept, killed
# ones resume from their checkpoints; a larger SEEDS adds seeds, a larger CYCLES continues the
# finished runs). Changing VELOCITY or SETS needs another OUT, as do the run folders of this script
# before studies/trust/ (their case.toml lacks the step). It runs for days on a 2-core machine
# (docs/studies.md, "Regenerating the studies"); in the background:
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
jobs_arg=${JOBS:+ --jobs $JOBS}
mkdir -p "$OUT" "$DOCS/data"
studies=("$@")
all=(underpressure friction young radius damping velocity paper_velocity calibration)
[ ${#studies[@]} -gt 0 ] || studies=("${all[@]}")
for s in "${studies[@]}"; do  # every name checked before anything runs
  [[ " ${all[*]} " == *" $s "* ]] || { echo "trust_studies.sh: unknown study '$s' (studies: ${all[*]})" >&2; exit 2; }
done
failed=0

# The knobs as the sweeps take them: the ensembles' (SEEDS, CYCLES, SETS, then VELOCITY but for the
# velocity study), the same for the friction study's calibration (its case.toml must match).
knobs="--seeds $SEEDS --set process.cycles=$CYCLES${SETS:+ $SETS}"
velocity_set="--set process.velocity=$VELOCITY"

# run_sweep NAME CMD: runs a study's sweep; 1 (some cases failed: the others are published) is
# noted, 2 (the sweep refused to run: a bad study or knob, a folder in use) ends the script.
run_sweep() {
  local name=$1 cmd=$2 rc=0
  echo "== $name: $cmd"
  $cmd || rc=$?
  [ $rc -ne 2 ] || { echo "trust_studies.sh: $name: the sweep refused to run (above)" >&2; exit 2; }
  if [ $rc -ne 0 ]; then
    echo "trust_studies.sh: $name: some runs failed (their rows in $OUT/$name/summary.csv say why)" >&2
    failed=1
  fi
}

# sweep NAME [--set ...]: studies/trust/NAME.toml with the knobs into $OUT/NAME, then publishes its
# summaries and figures as study_NAME_*.
sweep() {
  local name=$1 prefix=study_$1
  shift
  local cmd="$VPPDEM sweep studies/trust/$name.toml --out $OUT/$name $knobs${*:+ $*}$jobs_arg --no-plot"
  run_sweep "$name" "$cmd"
  $PLOT "$OUT/$name" --kind sweep --prefix "$prefix" --caption "$cmd"
  publish "$OUT/$name/${prefix}_W.png" "$DOCS/${prefix}_W.png"
  publish "$OUT/$name/${prefix}_loops.png" "$DOCS/${prefix}_loops.png"
  publish "$OUT/$name/summary.csv" "$DOCS/data/${prefix}_summary.csv"
  publish "$OUT/$name/summary_cases.csv" "$DOCS/data/${prefix}_cases.csv"
  record "${prefix}_W.png, ${prefix}_loops.png, data/${prefix}_summary.csv, data/${prefix}_cases.csv" "$cmd"
}

for s in "${studies[@]}"; do
  case $s in
    underpressure | friction | young | radius | damping) sweep "$s" "$velocity_set" ;;
    velocity)
      sweep velocity
      cmd="$REPORT paired_velocity $OUT/velocity --out $OUT/velocity/study_velocity_paired"
      echo "== velocity, paired: $cmd"
      $cmd --caption "$cmd"
      publish "$OUT/velocity/study_velocity_paired.csv" "$DOCS/data/study_velocity_paired.csv"
      publish "$OUT/velocity/study_velocity_paired.png" "$DOCS/study_velocity_paired.png"
      record "study_velocity_paired.png, data/study_velocity_paired.csv" "$cmd"
      ;;
    paper_velocity)
      # One cycle at the paper's 3.33e-4 m/s, 0.06 MPa, from the velocity study's seed-1 sample
      # (samples_from = "velocity": the sibling folder), compared with that seed's first cycles at
      # the study's velocities (same sample, paired).
      [ -d "$OUT/velocity" ] || { echo "trust_studies.sh: paper_velocity branches from the samples of study 'velocity' ($OUT/velocity): run 'velocity' first" >&2; exit 2; }
      cmd="$VPPDEM sweep studies/trust/paper_velocity.toml --out $OUT/paper_velocity${SETS:+ $SETS}$jobs_arg --no-plot"
      run_sweep paper_velocity "$cmd"
      rcmd="$REPORT paper_velocity_cycle1 $OUT/velocity $OUT/paper_velocity --out $OUT/paper_velocity/paper_velocity_cycle1.csv"
      echo "== paper_velocity, cycle 1: $rcmd"
      $rcmd
      publish "$OUT/paper_velocity/paper_velocity_cycle1.csv" "$DOCS/data/paper_velocity_cycle1.csv"
      record "data/paper_velocity_cycle1.csv" "$cmd; $rcmd"
      ;;
    calibration)
      # A calibration that could fail, at the paper's geometry: the "experiment" is a run at
      # mu = 0.45 (between the grid values) from a seed the study does not run, written as a rig
      # would, with noise; the grid is the friction study's (same folder: no run is repeated).
      t="$OUT/calibration_truth"
      tcmd="$VPPDEM sweep studies/trust/calibration_truth.toml --out $t --set process.cycles=$CYCLES${SETS:+ $SETS} $velocity_set --no-plot"
      run_sweep calibration_truth "$tcmd"
      [ -f "$t/base/summary.json" ] || { echo "trust_studies.sh: calibration: the synthetic experiment's run did not finish (see $t/summary.csv)" >&2; failed=1; continue; }
      ecmd="$PY tools/synthetic_experiment.py $t/base/forces.csv $t/base/experiment.csv"
      $ecmd
      cmd="$VPPDEM calibrate studies/trust/friction.toml --experiment $t/base/experiment.csv --out $OUT/friction $knobs $velocity_set$jobs_arg --time-column t_s --displacement-column stroke_mm --force-column load_kN --displacement-unit mm --force-unit kN --compression-negative"
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
        record "calibration_synthetic.png, data/calibration_synthetic*.csv, data/calibration_synthetic.json" "$tcmd; $ecmd; $cmd"
      fi
      ;;
  esac
done
if [ $failed -eq 0 ]; then echo "trust_studies.sh: done"; else echo "trust_studies.sh: done, with failures (see above)"; fi
exit $failed
