#!/usr/bin/env bash
# The damper at its working frequencies with the air inside (issue 23; docs/operation.md): two
# study files, one `vppdem sweep` each, then the report:
#   pump      examples/operation/pump.toml: a 2 m^3/h pump, triangle and sine, 1-20 Hz, 3 seeds; the
#             first case of each seed prepares the seed's sample
#   constant  examples/operation/constant.toml: its constant-model twin at 1, 5, 10, 20 Hz (where the
#             pump may fall behind, and one where it should not); it prepares nothing: each case
#             branches from its seed's sample in the sibling folder $OUT/pump (samples_from = "pump",
#             matched by geometry; summary.json "from" names it), so pump runs first
# Each sweep keeps its finished runs' small records (case.toml, summary.json, cycles.csv, build.json)
# and its tables in $DATA/STUDY (`--publish`), and first puts the records there back into $OUT/STUDY,
# where they count as finished: on a new machine, or again, nothing runs that $DATA holds. Then
# `python3 -m vppdem.report operation $DATA $DOCS --runs $OUT` keeps the last cycle of forces.csv of
# seed 1's 10 and 20 Hz runs that ran here ($DATA/STUDY/<case>/forces_last_cycle.csv; a run put back
# from $DATA has no forces.csv, and its published last cycle stays) and writes docs/operation.md and
# its figures from $DATA.
#
# usage: bash examples/operation/run.sh [--report-only]
#   --report-only: run nothing; the report from $DATA (no binary needed).
# Knobs (environment variables):
#   VPPDEM   the binary (default build/vppdem: bash scripts/build.sh vppdem)
#   OUT      run folders (default out/operation; $OUT/pump and $OUT/constant)
#   JOBS     runs at once (--jobs; default: vppdem's choice, the free cores)
#   SEEDS    seeds per case (--seeds; default the study files' 3)
#   SETS     further overrides for every run, e.g. SETS="--set process.cycles=1" (default none)
#   DATA     the published records (default docs/data/operation)
#   DOCS     where operation.md and its figures go (default docs)
# SAMPLES (a folder of prepared samples s1.ckpt ... s3.ckpt, copied into the cases by the script
# before the study files had samples_from) is gone: the pump study prepares its samples and the
# constant study branches from them. To start from other samples, give a copy of pump.toml a
# samples_from of its own.
#
# The published runs (docs/data/operation/) were made by the build deaa32a (pinned/op/vppdem; the
# commands in docs/data/operation/*/COMMAND, which this script leaves as they are and the report
# does not read) at simulation.dt_safety = 0.45, the default then; every case started from its
# seed's 25.5 mm sample of the paper's radius study (SAMPLES=out/prep25), the sample the pump study
# prepares itself at that step. The default is 0.3 since issue 44, and the study files do not set
# the step: with simulation.dt_safety in [set] or in SETS, a case.toml has a key the published ones
# lack, which makes it another case, and every published run is refused as a run of other settings.
# So a run that $DATA lacks (a record removed, more SEEDS) runs at 0.3 beside the published 0.45
# runs. To rerun the study as published, at 0.45, give new folders:
#   OUT=out/operation045 DATA=out/operation045/data DOCS=out/operation045/docs \
#     SETS="--set simulation.dt_safety=0.45" bash examples/operation/run.sh
# (checked 2026-11-27 with the build of 49d6d4f: the pump study's triangle at 20 Hz, seed 1, at 0.45
# gives the published cycles.csv byte for byte, from out/prep25/s1.ckpt and from a preparation of
# its own alike).
# Resumable: the same command again continues where it stopped (finished runs kept, killed ones
# continue from their run.ckpt). The published runs took 272 core-minutes (pump 153, constant 119:
# summary.json run_seconds) beside the 3 preparations: about 2.5 hours on 2 cores from nothing.
set -euo pipefail
cd "$(dirname "$0")/../.."
VPPDEM=${VPPDEM:-build/vppdem}
OUT=${OUT:-out/operation}
JOBS=${JOBS:-}
SEEDS=${SEEDS:-}
SETS=${SETS:-}
DATA=${DATA:-docs/data/operation}
DOCS=${DOCS:-docs}
PY=/usr/bin/python3  # Debian's, with matplotlib and numpy
[ -x "$PY" ] || PY=$(command -v python3)
# The report: the package's vppdem.report from the source tree (it needs no compiled module).
REPORT="env PYTHONPATH=src/python $PY -m vppdem.report"
report_only=0
if [ $# -eq 1 ] && [ "$1" = --report-only ]; then
  report_only=1
elif [ $# -gt 0 ]; then
  echo "run.sh: unknown argument(s) '$*' (usage: bash examples/operation/run.sh [--report-only])" >&2
  exit 2
fi
if [ -n "${SAMPLES:-}" ]; then
  echo "run.sh: SAMPLES is gone: the pump study prepares its samples and constant.toml branches from them (samples_from); see the header" >&2
  exit 2
fi

failed=0
runs=()
if [ $report_only -eq 0 ]; then
  [ -x "$VPPDEM" ] || { echo "run.sh: no vppdem binary at $VPPDEM (build it: bash scripts/build.sh vppdem)" >&2; exit 2; }
  # whole_knobs WHO NAME...
  source scripts/publish.sh
  [ -z "$JOBS" ] || whole_knobs run.sh JOBS
  [ -z "$SEEDS" ] || whole_knobs run.sh SEEDS
  mkdir -p "$OUT"
  for study in pump constant; do
    cmd="$VPPDEM sweep examples/operation/$study.toml --out $OUT/$study --publish $DATA/$study${SEEDS:+ --seeds $SEEDS}${SETS:+ $SETS}${JOBS:+ --jobs $JOBS} --no-plot"
    echo "== $study: $cmd"
    rc=0
    $cmd || rc=$?
    # 1: some runs failed (the others are published); 2: the sweep refused to run.
    [ $rc -ne 2 ] || { echo "run.sh: $study: the sweep refused to run (above)" >&2; exit 2; }
    [ $rc -eq 0 ] || { echo "run.sh: $study: some runs failed (see $OUT/$study/summary.csv)" >&2; failed=1; }
  done
  runs=(--runs "$OUT")
fi
mkdir -p "$DOCS"
$REPORT operation "$DATA" "$DOCS" "${runs[@]}"
exit $failed
