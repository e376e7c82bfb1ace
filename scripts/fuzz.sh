#!/usr/bin/env bash
# Fuzzes the readers of user files (issue 25; docs/robustness.md): builds the libFuzzer targets
# of fuzz/ with clang in build-fuzz/ (-DVPPDEM_FUZZ=ON: ASan, UBSan, coverage) and runs each
# for SECONDS, one after the other, niced (the machine also runs simulations).
#   usage: scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET ...]     (default 600 s, every target)
# Each target starts from its seeds (fuzz/corpus/<target>) and the kept findings
# (fuzz/regressions/<target>); what it learns goes to build-fuzz/corpus/<target> (read again by
# the next run, never written into the repository). A finding (crash, sanitizer report, an
# exception other than the reader's documented errors, a run over 10 s, over 2 GB) stops its
# target and is written to build-fuzz/findings/<target>/; the log is build-fuzz/logs/<target>.log.
# Once the reader is fixed, copy the input to fuzz/regressions/<target>/ so that the test
# Fuzz.Replay.<target> (every build) keeps it fixed.
# Prints per target: seconds, executions (total, per second), new inputs, findings of this run.
set -euo pipefail
cd "$(dirname "$0")/.."

all_targets=(config set study scene experiment numeric_csv checkpoint stl)
seconds=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all_targets[@]}")

# Longest input per target: well above the seeds, small enough that a mutation stays cheap. The
# checkpoint's seed is a whole damper's state (about 40 KB).
max_len() {
  case "$1" in
    set) echo 1024 ;;
    checkpoint) echo 65536 ;;
    *) echo 8192 ;;
  esac
}

if ! command -v clang++ > /dev/null; then
  echo "fuzz.sh: clang++ not found (apt-get install clang; libFuzzer comes with it)" >&2
  exit 1
fi
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVPPDEM_FUZZ=ON \
  -DVPPDEM_TESTS=OFF -DVPPDEM_BENCHMARKS=OFF -DVPPDEM_PYTHON=OFF > /dev/null
mkdir -p build-fuzz/logs
if ! nice -n 10 cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]/#/fuzz_}" > build-fuzz/logs/build.log 2>&1; then
  tail -40 build-fuzz/logs/build.log >&2
  exit 1
fi

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
summary=""
for t in "${targets[@]}"; do
  mkdir -p "build-fuzz/corpus/$t" "build-fuzz/findings/$t"
  seeds=("fuzz/corpus/$t")
  [ -d "fuzz/regressions/$t" ] && seeds+=("fuzz/regressions/$t")
  stamp=$(mktemp)
  start=$(date +%s)
  echo "fuzz.sh: $t for $seconds s (log: build-fuzz/logs/$t.log)" >&2
  # A finding ends the run with a nonzero status: reported below, the other targets still run.
  nice -n 10 "build-fuzz/fuzz/fuzz_$t" "build-fuzz/corpus/$t" "${seeds[@]}" \
    -max_total_time="$seconds" -max_len="$(max_len "$t")" -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="build-fuzz/findings/$t/" -print_final_stats=1 > "build-fuzz/logs/$t.log" 2>&1 &
  pid=$!
  wait "$pid" || true
  # The target's input folder (fuzz/fuzz_input.h): an abort skips the target's own clean-up.
  rm -rf "/dev/shm/vppdem_fuzz_$pid" "${TMPDIR:-/tmp}/vppdem_fuzz_$pid"
  took=$(( $(date +%s) - start ))
  stat() { sed -n "s/^stat::$1: *//p" "build-fuzz/logs/$t.log" | tail -1; }
  execs=$(stat number_of_executed_units)
  rate=$(stat average_exec_per_sec)
  added=$(stat new_units_added)
  new_findings=$(find "build-fuzz/findings/$t" -type f -newer "$stamp")
  rm -f "$stamp"
  found=$(printf '%s' "$new_findings" | grep -c . || true)
  summary+=$(printf '%-12s %8s %12s %10s %8s %9s' "$t" "$took" "${execs:-?}" "${rate:-?}" "${added:-?}" "$found")$'\n'
  if [ "$found" -gt 0 ]; then
    printf '%s\n' "$new_findings" | sed 's/^/  finding: /' >&2
    grep -m1 -E "ERROR: |runtime error|terminate called|fuzz: the error" "build-fuzz/logs/$t.log" | sed 's/^/  /' >&2 || true
  fi
done
printf '\n%-12s %8s %12s %10s %8s %9s\n' target seconds executions exec/s new findings
printf '%s' "$summary"
