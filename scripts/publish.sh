# Shared by scripts/trust_studies.sh and scripts/velocity_convergence.sh (sourced, not run):
# publishing results into docs/ and recording where they came from. Needs DOCS (the docs folder).

# Copies FILE to DEST through a temporary name (a reader never sees half a file).
publish() {
  cp "$1" "$2.part" && mv -f "$2.part" "$2"
}

# Records in $DOCS/data/SOURCES.md that FILE(S) came from COMMAND (one row per file set; a new
# row for the same files replaces the old one).
record() {
  local files=$1 cmd=$2 src="$DOCS/data/SOURCES.md"
  [ -f "$src" ] || printf '# Where the files in docs/ come from\n\nWritten by scripts/trust_studies.sh and scripts/velocity_convergence.sh; one line per file set: the files, the command, when, the vppdem commit.\n\n| files | command | date | commit |\n|---|---|---|---|\n' > "$src"
  local commit
  commit=$(git rev-parse --short HEAD 2>/dev/null || echo "?")
  { grep -v -F "| $files |" "$src" || true; printf '| %s | `%s` | %s | %s |\n' "$files" "$cmd" "$(date -u +%Y-%m-%d)" "$commit"; } > "$src.part"
  mv -f "$src.part" "$src"
}
