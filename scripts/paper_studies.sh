#!/usr/bin/env bash
# Runs the paper's studies (issues 20, 44: studies/paper/*.toml, 0.01 m/s, 3-5 seeds, 5 cycles),
# one `vppdem sweep` each, and keeps every finished run's small records in the repository
# (docs/data/paper/<study>/<case>/: case.toml, summary.json, cycles.csv; and the study's tables),
# so that a new machine loses at most the runs in flight. What a study does (its grid, seeds,
# the samples it branches from, the runs it continues) is in its study file; this script only
# picks the binary and publishes.
#
# usage: scripts/paper_studies.sh [--publish-only] [STUDY ...]
#   STUDY: underpressure radius_underpressure friction damping young preparation foil_resolution
#          timestep radius_packing (default: all, in this order); the second legs friction_8 and
#          friction_8_seeds when named (after the friction and radius studies they continue).
#          underpressure is the radius study's 25.5 mm rows alone, run into its folder.
#   --publish-only: publish what has finished and stop (while runs go on).
# One study, one build (docs/data/SOURCES.md names each study's):
#   VPPDEM          the studies' pinned binary (default pinned/vppdem): underpressure ... foil_resolution
#   VPPDEM_PACKING  radius_packing's (default pinned/packing/vppdem): the first with damper.packing_target
#   VPPDEM_NOW      this build (default build/vppdem): timestep, friction_8 and friction_8_seeds, whose
#                   study files use samples_from and continues, keys the pinned builds predate (their
#                   published runs, made by scripts before those keys, count as finished: nothing
#                   runs again unless a record is removed); and the publishing of every study
#                   (`vppdem sweep --report-only --publish`).
#   Beside each pinned binary a COMMIT file names its commit; a binary of another commit than a
#   study's published runs is refused (those builds predate build.json, by which the sweep itself
#   refuses to mix builds). The pinned builds predate --publish too: this build's
#   `sweep --report-only --publish` puts the published records back into OUT before the pinned
#   sweep runs, and publishes its finished runs and the COMMAND this script writes after it.
#   OUT   run folders (default out/paper; checkpoints and full records, not in the repository)
#   JOBS  runs at once (default: vppdem's choice, the free cores)
#   DATA  where the records go (default docs/data/paper)
# Resumable: the same command again continues (published records are put back into OUT first,
# killed runs continue from their run.ckpt). In the background:
#   nohup nice -n 19 bash scripts/paper_studies.sh > paper.log 2>&1 &
set -euo pipefail
cd "$(dirname "$0")/.."

VPPDEM=${VPPDEM:-pinned/vppdem}
VPPDEM_PACKING=${VPPDEM_PACKING:-pinned/packing/vppdem}
VPPDEM_NOW=${VPPDEM_NOW:-build/vppdem}
OUT=${OUT:-out/paper}
JOBS=${JOBS:-}
DATA=${DATA:-docs/data/paper}
publish_only=0
if [ "${1:-}" = "--publish-only" ]; then publish_only=1; shift; fi
all=(underpressure radius_underpressure friction damping young preparation foil_resolution timestep radius_packing)
legs=(friction_8 friction_8_seeds)
studies=("$@")
[ ${#studies[@]} -gt 0 ] || studies=("${all[@]}")
for s in "${studies[@]}"; do
  [[ " ${all[*]} ${legs[*]} " == *" $s "* ]] || { echo "paper_studies.sh: unknown study '$s' (studies: ${all[*]}; second legs: ${legs[*]})" >&2; exit 2; }
done
# The binary that runs STUDY, and the folder it runs into.
binary() { case "$1" in timestep | friction_8*) echo "$VPPDEM_NOW" ;; radius_packing) echo "$VPPDEM_PACKING" ;; *) echo "$VPPDEM" ;; esac; }
folder() { if [ "$1" = underpressure ]; then echo radius_underpressure; else echo "$1"; fi; }
for s in "${studies[@]}"; do
  for b in "$VPPDEM_NOW" "$(binary "$s")"; do
    [ $publish_only -eq 1 ] && [ "$b" != "$VPPDEM_NOW" ] && continue
    [ -x "$b" ] || { echo "paper_studies.sh: $s: no vppdem binary at $b (build: bash scripts/build.sh; a pinned one: mkdir -p DIR && cp build/vppdem DIR/ && git rev-parse HEAD > DIR/COMMIT)" >&2; exit 2; }
  done
done
# whole_knobs WHO NAME...
source scripts/publish.sh
[ -z "$JOBS" ] || whole_knobs paper_studies.sh JOBS
jobs_arg=()
[ -z "$JOBS" ] || jobs_arg=(--jobs "$JOBS")

failed=0
for study in "${studies[@]}"; do
  f=$(folder "$study") bin=$(binary "$study")
  file=studies/paper/$study.toml
  # Publishing: the published records back into OUT/f first, then every finished case's records,
  # the tables and OUT/f/COMMAND into DATA/f (the current build's report of the runs; it runs
  # nothing and reads runs of any build).
  publish_cmd=("$VPPDEM_NOW" sweep "$file" --out "$OUT/$f" --report-only --mix-builds --publish "$DATA/$f" --no-plot --quiet)
  if [ $publish_only -eq 1 ]; then
    [ -d "$OUT/$f" ] && { "${publish_cmd[@]}" || failed=1; }
    continue
  fi
  mkdir -p "$OUT/$f"
  if [ "$bin" = "$VPPDEM_NOW" ]; then
    # One command: the published records back, the study run (branching from the other studies'
    # samples in OUT, continuing their runs), the finished runs published. friction_8 continues
    # the friction study's runs, which another build made: --mix-builds.
    mix=()
    [ "$study" != friction_8 ] || mix=(--mix-builds)
    cmd=("$bin" sweep "$file" --out "$OUT/$f" --publish "$DATA/$f" "${mix[@]}" "${jobs_arg[@]}" --no-plot)
    echo "== $study: ${cmd[*]}"
    "${cmd[@]}" || failed=1
    continue
  fi
  # One study, one build: the COMMAND of the published records and of the run folder names the
  # pinned build of their runs; a binary of another commit, or without a COMMIT file, is refused.
  commit=$(cat "$(dirname "$bin")/COMMIT" 2>/dev/null || true)
  [ -n "$commit" ] || { echo "paper_studies.sh: no COMMIT file beside the binary: write the commit it was built from into it (see the script's header)" >&2; exit 2; }
  for dir in "$DATA/$f" "$OUT/$f"; do
    held=$(sed -n 's/.*(pinned build \([^)]*\)).*/\1/p' "$dir/COMMAND" 2>/dev/null | head -n 1 || true)
    [ -z "$held" ] || [ "$held" = "$commit" ] || {
      echo "paper_studies.sh: the runs in $dir came from the pinned build $held; this binary's COMMIT says $commit." >&2
      echo "paper_studies.sh: one study, one build: rebuild $held and pin it (see the script's header), or give new DATA and OUT folders" >&2
      exit 2
    }
  done
  # The published records back (the pinned builds have no --publish); without them the pinned
  # sweep would run again what is published.
  "${publish_cmd[@]}" || { failed=1; continue; }
  cmd=("$bin" sweep "$file" --out "$OUT/$f" "${jobs_arg[@]}" --no-plot)
  echo "== $study: ${cmd[*]}"
  # The radius study's COMMAND names the whole study (its 25.5 mm rows are the same cases).
  if [ "$study" != underpressure ]; then
    printf '%s (pinned build %s)\n' "${cmd[*]}" "$commit" > "$OUT/$f/COMMAND"
  elif [ ! -f "$OUT/$f/COMMAND" ]; then
    printf '%s (pinned build %s)\n' "$bin sweep studies/paper/radius_underpressure.toml --out $OUT/$f ${jobs_arg[*]} --no-plot" \
      "$commit" > "$OUT/$f/COMMAND"
  fi
  "${cmd[@]}" || failed=1
  "${publish_cmd[@]}" || failed=1
done
exit $failed
