# Shared by the scripts that run studies (sourced, not run). A study's records and tables are
# published by `vppdem sweep --publish DIR` (and `--report-only --publish DIR`) alone; here is
# what it does not do: the copies of a report's outputs (figures, tables under the names docs/
# gives them) and their rows in docs/data/SOURCES.md, for scripts/trust_studies.sh,
# velocity_convergence.sh and settle_cycles.sh, and the knobs' check of every study script.
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
