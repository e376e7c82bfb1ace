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
