#!/usr/bin/env bash
# Reruns the velocity convergence measured for issue 12 and publishes its tables and figures
# (docs/studies.md, "Velocity convergence: results"):
#   quick       the paper's damper, dp 0.02 / 0.06 MPa x 0.1 ... 0.01 m/s, 2 cycles, SEEDS_QUICK seeds
#               (examples/study_velocity_quick.toml; about 3 hours on the 2-core machine)
#   small       the small damper, dp 0.02 / 0.06 MPa x 0.1 ... 0.002 m/s, 3 cycles, SEEDS_SMALL seeds
#               (examples/study_velocity_small.toml; about 40 minutes on one core)
#   small_paper one cycle at the paper's 3.33e-4 m/s from every small-damper sample (about 10
#               minutes each)
#   quick_slow  the paper's damper at 0.005 m/s, 0.02 and 0.06 MPa, 2 cycles, from every sample of
#               'quick' (about 25 minutes each on one core)
#   quick_paper one cycle of the paper's damper at the paper's 3.33e-4 m/s, 0.06 MPa, from the
#               first SEEDS_PAPER samples of 'quick' (3.26e7 steps: about 72 minutes on 2 threads;
#               a checkpoint every minute, so a stopped run resumes)
# usage: scripts/velocity_convergence.sh [PART ...]   (default: all five, in this order)
# Knobs: VPPDEM (default build/vppdem), OUT (default out/velocity), SEEDS_QUICK (2), SEEDS_SMALL (3),
#        SEEDS_PAPER (1),
#        JOBS (runs at once; default the free cores), DOCS (default docs).
# Resumable: the same command continues where it stopped. In the background:
#   nohup nice -n 19 bash scripts/velocity_convergence.sh > velocity.log 2>&1 &
set -euo pipefail
cd "$(dirname "$0")/.."

VPPDEM=${VPPDEM:-build/vppdem}
OUT=${OUT:-out/velocity}
SEEDS_QUICK=${SEEDS_QUICK:-2}
SEEDS_SMALL=${SEEDS_SMALL:-3}
SEEDS_PAPER=${SEEDS_PAPER:-1}
JOBS=${JOBS:-}
DOCS=${DOCS:-docs}
PY=/usr/bin/python3  # Debian's, with matplotlib and numpy
# The report: the package's vppdem.report from the source tree (it needs no compiled module).
REPORT="env PYTHONPATH=src/python $PY -m vppdem.report"

[ -x "$VPPDEM" ] || { echo "velocity_convergence.sh: no vppdem binary at $VPPDEM (build it: bash scripts/build.sh)" >&2; exit 2; }
# publish FILE DEST, record FILES COMMAND, whole_knobs WHO NAME...
source scripts/publish.sh
whole_knobs velocity_convergence.sh SEEDS_QUICK SEEDS_SMALL SEEDS_PAPER
[ -z "$JOBS" ] || whole_knobs velocity_convergence.sh JOBS
jobs_arg=${JOBS:+--jobs $JOBS}
parts=("$@")
all=(quick small small_paper quick_slow quick_paper)
[ ${#parts[@]} -gt 0 ] || parts=("${all[@]}")
for s in "${parts[@]}"; do
  [[ " ${all[*]} " == *" $s "* ]] || { echo "velocity_convergence.sh: unknown part '$s' (parts: ${all[*]})" >&2; exit 2; }
done
mkdir -p "$OUT" "$DOCS/data"

analyse() {  # NAME SWEEP_DIR [--extra DIRS...]
  local name=$1 dir=$2
  shift 2
  local cmd="$REPORT velocity_cycles $dir $* --out $dir/$name"
  echo "== $name: $cmd"
  $cmd --caption "$cmd"
  publish "$dir/$name.csv" "$DOCS/data/$name.csv"
  publish "$dir/$name.png" "$DOCS/$name.png"
  publish "$dir/summary.csv" "$DOCS/data/${name}_summary.csv"
  record "$name.png, data/$name.csv, data/${name}_summary.csv" "$cmd"
}

# run_branch DIR CKPT [--set ...]: one damper run branched from CKPT into DIR; resumes a killed
# run from DIR/run.ckpt and skips a finished one.
run_branch() {
  local d=$1 ckpt=$2
  shift 2
  if [ -f "$d/summary.json" ]; then echo "   $d done earlier"; return; fi
  if [ -f "$d/run.ckpt" ]; then $VPPDEM damper --from "$d/run.ckpt" --out "$d" --no-plot --quiet; return; fi
  echo "== $d"
  $VPPDEM damper --from "$ckpt" --out "$d" --no-plot --quiet "$@"
}

# finished_branches PREFIX SEEDS DP...: the finished runs $OUT/PREFIX_dpDP_sS, DP by DP, seed by seed.
finished_branches() {
  local prefix=$1 seeds=$2 dp s
  shift 2
  for dp in "$@"; do
    for s in $(seq "$seeds"); do
      [ -f "$OUT/${prefix}_dp${dp}_s$s/summary.json" ] && echo "$OUT/${prefix}_dp${dp}_s$s"
    done
  done
  return 0
}

quick_slow_dirs() {
  finished_branches quick_v0.005 "$SEEDS_QUICK" 0.02e6 0.06e6
  finished_branches quick_paper "$SEEDS_PAPER" 0.06e6
}

small_paper_dirs() { finished_branches small_paper "$SEEDS_SMALL" 0.02e6 0.06e6; }

for part in "${parts[@]}"; do
  case $part in
    quick)
      cmd="$VPPDEM sweep examples/study_velocity_quick.toml --out $OUT/quick --seeds $SEEDS_QUICK --set simulation.threads=1 $jobs_arg --no-plot"
      echo "== quick: $cmd"
      $cmd || echo "velocity_convergence.sh: quick: some runs failed (see $OUT/quick/summary.csv)" >&2
      analyse velocity_quick "$OUT/quick"
      ;;
    small)
      cmd="$VPPDEM sweep examples/study_velocity_small.toml --out $OUT/small --seeds $SEEDS_SMALL --set simulation.threads=1 $jobs_arg --no-plot"
      echo "== small: $cmd"
      $cmd || echo "velocity_convergence.sh: small: some runs failed (see $OUT/small/summary.csv)" >&2
      analyse velocity_small "$OUT/small"
      ;;
    small_paper)
      for dp in 0.02e6 0.06e6; do
        for s in $(seq "$SEEDS_SMALL"); do
          ckpt=$(ls "$OUT"/small/*simulation.seed=$s/prepared.ckpt 2>/dev/null | head -1 || true)
          [ -n "$ckpt" ] || { echo "velocity_convergence.sh: small_paper needs the small study's samples: run 'small' first" >&2; exit 2; }
          run_branch "$OUT/small_paper_dp${dp}_s$s" "$ckpt" --set process.velocity=3.33e-4 --set process.cycles=1 \
            --set process.underpressure=$dp --set process.amplitude=0.002 --set process.samples_per_cycle=200 \
            --set output.energy=true --set simulation.threads=1
        done
      done
      # shellcheck disable=SC2046
      analyse velocity_small "$OUT/small" --extra $(small_paper_dirs)
      ;;
    quick_slow)
      for dp in 0.02e6 0.06e6; do
        for s in $(seq "$SEEDS_QUICK"); do
          ckpt=$(ls "$OUT"/quick/*simulation.seed=$s/prepared.ckpt 2>/dev/null | head -1 || true)
          [ -n "$ckpt" ] || { echo "velocity_convergence.sh: quick_slow needs the quick study's samples: run 'quick' first" >&2; exit 2; }
          run_branch "$OUT/quick_v0.005_dp${dp}_s$s" "$ckpt" --set process.velocity=0.005 --set process.cycles=2 \
            --set process.underpressure=$dp --set output.energy=false --set simulation.threads=1
        done
      done
      # shellcheck disable=SC2046
      analyse velocity_quick "$OUT/quick" --reference 0.005 --extra $(quick_slow_dirs)
      ;;
    quick_paper)
      for s in $(seq "$SEEDS_PAPER"); do
        ckpt=$(ls "$OUT"/quick/*simulation.seed=$s/prepared.ckpt 2>/dev/null | head -1 || true)
        [ -n "$ckpt" ] || { echo "velocity_convergence.sh: quick_paper needs the quick study's samples: run 'quick' first" >&2; exit 2; }
        run_branch "$OUT/quick_paper_dp0.06e6_s$s" "$ckpt" --set process.velocity=3.33e-4 --set process.cycles=1 \
          --set process.underpressure=0.06e6 --set output.energy=false --set simulation.threads=2
      done
      # shellcheck disable=SC2046
      analyse velocity_quick "$OUT/quick" --reference 0.005 --extra $(quick_slow_dirs)
      ;;
  esac
done
