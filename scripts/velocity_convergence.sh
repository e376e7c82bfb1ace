#!/usr/bin/env bash
# Reruns the velocity convergence measured for issue 12 and publishes its tables and figures
# (docs/studies.md, "Velocity convergence: results"). Each part is one study file of
# studies/velocity/ run by one `vppdem sweep` into $OUT/PART, then the analysis of its base study
# (python3 -m vppdem.report velocity_cycles):
#   quick       the paper's damper, dp 0.02 / 0.06 MPa x 0.1 ... 0.01 m/s, 2 cycles, SEEDS_QUICK seeds
#               (studies/velocity/quick.toml; about 3 hours on the 2-core machine)
#   small       the small damper, dp 0.02 / 0.06 MPa x 0.1 ... 0.002 m/s, 3 cycles, SEEDS_SMALL seeds
#               (studies/velocity/small.toml; about 40 minutes on one core)
#   small_paper one cycle at the paper's 3.33e-4 m/s, both dp, from every sample of 'small'
#               (studies/velocity/small_paper.toml; about 10 minutes each)
#   quick_slow  the paper's damper at 0.005 m/s, 0.02 and 0.06 MPa, 2 cycles, from every sample of
#               'quick' (studies/velocity/quick_slow.toml; about 25 minutes each on one core)
#   quick_paper one cycle of the paper's damper at the paper's 3.33e-4 m/s, 0.06 MPa, from the
#               first SEEDS_PAPER samples of 'quick' (studies/velocity/quick_paper.toml; 3.26e7
#               steps: about 72 minutes on 2 threads; a checkpoint every minute, so a stopped run
#               resumes)
# The last three prepare nothing: their study files branch each seed's cases from that seed's
# sample in the sibling folder $OUT/small or $OUT/quick (samples_from, matched by geometry and
# seed; summary.json "from" names it), so run their base part first. Every study file sets
# simulation.dt_safety = 0.45, the published runs' step (0.3 is the default now).
# After each part its base study is analysed with the branch parts run so far and published:
# $DOCS/velocity_NAME.png, $DOCS/data/velocity_NAME.csv and the base sweep's summary.csv as
# $DOCS/data/velocity_NAME_summary.csv (NAME quick or small), each command in
# $DOCS/data/SOURCES.md; no `--publish` (docs/data holds these tables only); then the tables and verdicts
# of docs/studies.md's "Velocity convergence: results" (velocity_cycles --page). docs/studies.md,
# "Rerunning the measurement".
# usage: scripts/velocity_convergence.sh [PART ...]   (default: all five, in this order)
# Knobs: VPPDEM (default build/vppdem), OUT (default out/velocity), SEEDS_QUICK (2: quick,
#        quick_slow), SEEDS_SMALL (3: small, small_paper), SEEDS_PAPER (1: quick_paper) (the sweeps'
#        --seeds), JOBS (runs at once; default the free cores), DOCS (default docs).
# Resumable: the same command continues where it stopped (finished cases kept, killed ones continue
# from their run.ckpt); the branch run folders of the script before studies/velocity/
# ($OUT/small_paper_dp*_s*, quick_v0.005_*, quick_paper_dp*) are not picked up. In the background:
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
parts=("$@")
all=(quick small small_paper quick_slow quick_paper)
[ ${#parts[@]} -gt 0 ] || parts=("${all[@]}")
for s in "${parts[@]}"; do
  [[ " ${all[*]} " == *" $s "* ]] || { echo "velocity_convergence.sh: unknown part '$s' (parts: ${all[*]})" >&2; exit 2; }
done
mkdir -p "$OUT" "$DOCS/data"

# analyse NAME BASE [ARGS...] [-- BRANCH...]: the base study's runs in $OUT/BASE with those of the
# branch studies $OUT/BRANCH that exist (--extra), published as velocity_NAME.*.
analyse() {
  local name=$1 dir=$OUT/$2 args=() extra=() b
  shift 2
  while [ $# -gt 0 ] && [ "$1" != -- ]; do args+=("$1"); shift; done
  [ $# -eq 0 ] || shift
  for b in "$@"; do [ -d "$OUT/$b" ] && extra+=("$OUT/$b"); done
  [ ${#extra[@]} -eq 0 ] || args+=(--extra "${extra[@]}")
  local cmd="$REPORT velocity_cycles $dir ${args[*]:+${args[*]} }--out $dir/velocity_$name"
  echo "== velocity_$name: $cmd"
  $cmd --caption "$cmd"
  publish "$dir/velocity_$name.csv" "$DOCS/data/velocity_$name.csv"
  publish "$dir/velocity_$name.png" "$DOCS/velocity_$name.png"
  publish "$dir/summary.csv" "$DOCS/data/velocity_${name}_summary.csv"
  record "velocity_$name.png, data/velocity_$name.csv, data/velocity_${name}_summary.csv" "$cmd"
}

for part in "${parts[@]}"; do
  case $part in
    quick | quick_slow) seeds=$SEEDS_QUICK ;;
    small | small_paper) seeds=$SEEDS_SMALL ;;
    quick_paper) seeds=$SEEDS_PAPER ;;
  esac
  base=${part%%_*}  # the study whose runs the part's are analysed with (and a branch's samples)
  if [ "$part" != "$base" ] && [ ! -d "$OUT/$base" ]; then
    echo "velocity_convergence.sh: $part branches from the samples of part '$base' ($OUT/$base): run '$base' first" >&2
    exit 2
  fi
  cmd="$VPPDEM sweep studies/velocity/$part.toml --out $OUT/$part --seeds $seeds ${JOBS:+--jobs $JOBS }--no-plot"
  echo "== $part: $cmd"
  rc=0
  $cmd || rc=$?
  # 1: some cases failed (the others finished, and are analysed); 2: the study did not run.
  [ $rc -ne 2 ] || { echo "velocity_convergence.sh: $part: the sweep refused to run (above)" >&2; exit 2; }
  [ $rc -eq 0 ] || echo "velocity_convergence.sh: $part: some runs failed (see $OUT/$part/summary.csv)" >&2
  case $base in
    small) analyse small small -- small_paper ;;
    quick) analyse quick quick --reference 0.005 -- quick_slow quick_paper ;;
  esac
done
# docs/studies.md's "Velocity convergence: results" (its tables and the rules' verdicts) from the
# two published tables, once both are there.
if [ -f "$DOCS/data/velocity_quick.csv" ] && [ -f "$DOCS/data/velocity_small.csv" ] && [ -f "$DOCS/studies.md" ]; then
  $REPORT velocity_cycles --page "$DOCS/studies.md" "$DOCS/data/velocity_quick.csv" "$DOCS/data/velocity_small.csv"
fi
