# Shared by the scripts that run studies and publish their records (sourced, not run):
# scripts/paper_studies.sh, grain_shapes.sh, trust_studies.sh, velocity_convergence.sh, settle_cycles.sh.
# record() needs DOCS (the docs folder).

# whole_knobs WHO NAME...: each named environment knob must be an integer >= 1; otherwise the
# knob, its value and what is allowed are named, exit 2 (an optional knob: `[ -z "$JOBS" ] ||`).
whole_knobs() {
  local who=$1 v
  shift
  for v in "$@"; do
    [[ ${!v:-} =~ ^[1-9][0-9]*$ ]] || { echo "$who: $v = '${!v:-}': must be an integer >= 1" >&2; exit 2; }
  done
}

# Copies FILE to DEST through a temporary name of its own (a reader never sees half a file, and
# two scripts publishing at once do not share one).
publish() {
  local tmp
  tmp=$(mktemp --suffix=.part "$2.XXXXXX") || return 1
  cp "$1" "$tmp" && chmod 644 "$tmp" && mv -f "$tmp" "$2" || { rm -f "$tmp"; return 1; }
}

# Records in $DOCS/data/SOURCES.md that FILE(S) came from COMMAND (one row per file set; a new
# row for the same files replaces the old one). Two scripts recording at once take turns (a lock
# on the data folder), so that neither row is lost.
record() {
  local files=$1 cmd=$2 src="$DOCS/data/SOURCES.md" fd tmp commit
  mkdir -p "$DOCS/data"
  exec {fd}<"$DOCS/data"
  flock "$fd"
  [ -f "$src" ] || printf '# Where the files in docs/ come from\n\nWritten by scripts/trust_studies.sh and scripts/velocity_convergence.sh; one line per file set: the files, the command, when, the vppdem commit.\n\n| files | command | date | commit |\n|---|---|---|---|\n' > "$src"
  commit=$(git rev-parse --short HEAD 2>/dev/null || echo "?")
  tmp=$(mktemp --suffix=.part "$src.XXXXXX")
  { grep -v -F "| $files |" "$src" || true; printf '| %s | `%s` | %s | %s |\n' "$files" "$cmd" "$(date -u +%Y-%m-%d)" "$commit"; } > "$tmp"
  chmod 644 "$tmp" && mv -f "$tmp" "$src"
  exec {fd}<&-
}

# The small records of a finished study run (a case folder with summary.json): what is published
# into docs/data and what a resumed study needs back to take the case as done.
RUN_RECORDS=(case.toml cycles.csv summary.json)

# restore_records DATA OUT: each published case of DATA back into OUT/<case>, unless that folder
# has a summary.json of its own (the sweep then takes the case as done, and re-analyses it).
restore_records() {
  local data=$1 out=$2 d c f
  [ -d "$data" ] || return 0
  for d in "$data"/*/; do
    [ -f "$d/summary.json" ] || continue
    c=$(basename "$d")
    [ -f "$out/$c/summary.json" ] && continue
    mkdir -p "$out/$c"
    for f in "${RUN_RECORDS[@]}"; do [ -f "$d/$f" ] && publish "$d/$f" "$out/$c/$f"; done
  done
  return 0
}

# save_records OUT DATA: each finished case of OUT into DATA/<case> (files that changed), then the
# study's tables and its COMMAND; sets SAVED to the number of finished cases DATA holds then.
save_records() {
  local out=$1 data=$2 d c f
  SAVED=0
  [ -d "$out" ] || return 0
  mkdir -p "$data"
  for d in "$out"/*/; do
    [ -f "$d/summary.json" ] || continue
    # A case.toml newer than the summary: the case continues (a study given more cycles rewrites
    # it first); its records are those of the shorter run until it finishes again.
    [ "$d/case.toml" -nt "$d/summary.json" ] && continue
    c=$(basename "$d")
    mkdir -p "$data/$c"
    for f in "${RUN_RECORDS[@]}"; do
      [ -f "$d/$f" ] && ! cmp -s "$d/$f" "$data/$c/$f" && publish "$d/$f" "$data/$c/$f"
    done
  done
  # The study's tables: those of the sweep that ran last here. A sweep of part of the study (the
  # radius study's underpressure rows alone) or an older machine's run folders hold fewer finished
  # cases than the published table: that table stays.
  if [ -f "$out/summary.csv" ] && [ "$(ok_rows "$out/summary.csv")" -ge "$(ok_rows "$data/summary.csv")" ]; then
    for f in summary.csv summary_cases.csv; do [ -f "$out/$f" ] && publish "$out/$f" "$data/$f"; done
  fi
  [ -f "$out/COMMAND" ] && publish "$out/COMMAND" "$data/COMMAND"
  for d in "$data"/*/; do [ -f "$d/summary.json" ] && SAVED=$((SAVED + 1)); done
  return 0
}

# ok_rows TABLE: the finished cases a sweep's summary.csv lists (rows whose status is "ok"; the
# columns before status hold no comma); 0 for a missing table.
ok_rows() {
  [ -f "$1" ] || { echo 0; return 0; }
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "status") col = i; next }
           col && $col == "ok" { ++n } END { print n + 0 }' "$1"
}

# pinned_of DIR: the pinned build DIR/COMMAND names ("(pinned build <commit>)"), or nothing.
pinned_of() {
  [ -f "$1/COMMAND" ] || return 0
  sed -n 's/.*(pinned build \([^)]*\)).*/\1/p' "$1/COMMAND" | head -n 1
}

# check_pinned COMMIT WHO DIR...: one study, one build. A DIR/COMMAND (the published records'
# and the run folder's) names the pinned build of the runs there ("(pinned build <commit>)"); a
# binary of another commit would mix two builds' results in one study, so it is refused (exit 2)
# before anything runs, as is a binary without the COMMIT file that names its build. A DIR
# without COMMAND: nothing to compare.
check_pinned() {
  local commit=$1 who=$2 dir held
  shift 2
  if [ -z "$commit" ] || [ "$commit" = unknown ]; then
    echo "$who: no COMMIT file beside the binary: write the commit it was built from into it (see the script's header)" >&2
    exit 2
  fi
  for dir in "$@"; do
    held=$(pinned_of "$dir")
    if [ -n "$held" ] && [ "$held" != "$commit" ]; then
      echo "$who: the runs in $dir came from the pinned build $held; this binary's COMMIT says $commit." >&2
      echo "$who: one study, one build: rebuild $held and pin it (see the script's header), or give new DATA and OUT folders" >&2
      exit 2
    fi
  done
  return 0
}

# continue_runs SRC DST WHO SAMPLE_FN CASE...: a second leg of a study (the same runs, more
# cycles): each CASE that DST lacks is copied from SRC/<case> (through a hidden temporary folder,
# renamed when whole), so that the leg's sweep continues it from its run.ckpt while SRC keeps the
# first leg's records. A finished case whose run.ckpt is gone (its records restored on another
# machine) runs again from the prepared sample it started from, for all the leg's cycles: the
# function SAMPLE_FN CASE prints that sample's path, placed as DST/<case>/run.ckpt (a sample
# takes the case's settings); its first cycles are then the first leg's where the leg's build
# reproduces the first leg's bits (the report checks them). A case still running, never run, or
# with neither run.ckpt nor sample would be run by the leg from scratch, so they are named and
# nothing is copied (exit 2).
continue_runs() {
  local src=$1 dst=$2 who=$3 sample_fn=$4 c missing=()
  shift 4
  for c in "$@"; do
    [ -e "$dst/$c" ] && continue
    if [ ! -f "$src/$c/summary.json" ]; then missing+=("$c (not finished)")
    elif [ ! -f "$src/$c/run.ckpt" ] && [ ! -f "$("$sample_fn" "$c")" ]; then missing+=("$c (no run.ckpt, no sample)")
    fi
  done
  refuse_missing "$who: the leg continues every run of $src, and cannot continue:" \
    "; finish the study first (or prepare the missing samples)" "${missing[@]}"
  mkdir -p "$dst"
  for c in "$@"; do
    [ -e "$dst/$c" ] && continue
    if [ -f "$src/$c/run.ckpt" ]; then
      stage_case "$dst" "$c" "$who" copy_continuing "$src/$c"
    else
      stage_case "$dst" "$c" "$who" copy_sample "$("$sample_fn" "$c")"
    fi
  done
  return 0
}

# refuse_missing BEFORE AFTER ITEM...: with any ITEM, "BEFORE item, item...AFTER" on stderr and
# exit 2 (nothing staged); without, nothing.
refuse_missing() {
  local before=$1 after=$2
  shift 2
  [ $# -eq 0 ] && return 0
  local IFS=,
  local items=("$@")
  echo "$before${items[*]/#/ }$after" >&2
  exit 2
}
# stage_case DST CASE WHO FILL ARG: DST/CASE made whole or not at all: `FILL ARG TMP` fills a
# hidden temporary folder, renamed DST/CASE when it succeeded (the temporary of a copy that was
# killed is removed first); on failure WHO names the case (exit 1).
stage_case() {
  local dst=$1 c=$2 who=$3 fill=$4 arg=$5 tmp
  rm -rf "$dst/.$c".??????
  tmp=$(mktemp -d "$dst/.$c.XXXXXX") || { echo "$who: could not make a temporary folder in $dst" >&2; exit 1; }
  "$fill" "$arg" "$tmp" && chmod 755 "$tmp" && mv -T "$tmp" "$dst/$c" ||
    { rm -rf "$tmp"; echo "$who: could not make $dst/$c from ${arg:-(no sample)}" >&2; exit 1; }
}
# copy_continuing RUN TMP: a run's folder, case.toml made newer than summary.json: the run
# continues (save_records publishes it when the leg's sweep has written its longer records).
copy_continuing() { cp -a "$1/." "$2/" && touch "$2/case.toml"; }
# copy_sample SAMPLE TMP: a prepared sample as the case's run.ckpt (it takes the case's settings).
copy_sample() { [ -f "$1" ] && cp "$1" "$2/run.ckpt"; }

# start_from_samples DST WHO SAMPLE_FN CASE...: runs of a study that start from samples another
# study prepared (SAMPLE_FN CASE prints the path): each CASE that DST lacks gets its sample as
# DST/<case>/run.ckpt (through a hidden temporary folder, renamed when whole), so that the sweep
# runs it from there with the case's settings, as a branch does. A case whose sample is not there
# would be prepared again by the sweep (another sample, not the one the other cases share), so
# they are named and nothing is copied (exit 2).
start_from_samples() {
  local dst=$1 who=$2 sample_fn=$3 c missing=()
  shift 3
  for c in "$@"; do
    [ -e "$dst/$c" ] || [ -f "$("$sample_fn" "$c")" ] || missing+=("$c")
  done
  refuse_missing "$who: no prepared sample to start from for:" "; run the study that prepares it first" "${missing[@]}"
  mkdir -p "$dst"
  for c in "$@"; do
    if [ ! -e "$dst/$c" ]; then stage_case "$dst" "$c" "$who" copy_sample "$("$sample_fn" "$c")"; fi
  done
  return 0
}
