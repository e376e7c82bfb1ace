#!/usr/bin/env bash
# The test suite under AddressSanitizer and UndefinedBehaviorSanitizer (issue 25): a separate
# build in build-sanitize/ (-DVPPDEM_SANITIZE=ON, no Python module: a sanitized extension needs
# the runtime preloaded into the interpreter; no benchmarks), then every test; any report fails
# its test. Installs nothing: run the README's test command once first.
# usage: scripts/sanitize.sh [SUITE_REGEX]   (e.g. 'Study|Damper' for a part; default: all)
#
# Why not plain ctest: ctest runs each test in a process of its own, so a fixture's shared run
# (the Damper tests' small damper, SetUpTestSuite) is redone for every one of its tests: about
# 650 s each under ASan. Here the GoogleTest suites run one process per suite (the fixture runs
# once), up to $(nproc) at a time, the longest first; the other tests (layers, docs, the fuzz
# corpus replay) through ctest. The tests' wall-clock budgets for a run are scaled by
# VPPDEM_TEST_TIME_SCALE (default here 50; tests/physics/cli_helpers.h).
# Logs: build-sanitize/sanitize-logs/<suite>.log; the table of suites and seconds at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-.}
jobs=${JOBS:-$(nproc)}
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVPPDEM_SANITIZE=ON -DVPPDEM_PYTHON=OFF \
  -DVPPDEM_BENCHMARKS=OFF > /dev/null
cmake --build build-sanitize -j "$jobs"
cd build-sanitize
# detect_leaks: a leak is a report too; abort_on_error gives a core-free, nonzero exit.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export VPPDEM_TEST_TIME_SCALE=${VPPDEM_TEST_TIME_SCALE:-50}
start=$(date +%s)
failed=0

# The tests that are not GoogleTest's (any test name without a suite of vppdem_tests).
suites=$(./vppdem_tests --gtest_list_tests | grep -v '^ ' | awk '{print $1}' | sed 's/\.$//' | grep -E -- "$filter" || true)
others=$(ctest -N | sed -n 's/^ *Test *#[0-9]*: //p' | grep -v -E '^(python|Python)' |
  while read -r t; do s=${t%%.*}; grep -qx -- "$s" <<< "$suites" || echo "$t"; done | grep -E -- "$filter" || true)
if [ -n "$others" ]; then
  ctest --output-on-failure -j "$jobs" -R "^($(paste -sd'|' <<< "$others" | sed 's/\./\\./g'))\$" || failed=1
fi

# The slow suites first (they drive whole damper runs), so that the pool ends together.
slow='^(Damper|Study|Energy|EnergyBudget|Examples|Tools|Calibrat|Velocity|Envelope|Tension)'
ordered=$( (grep -E "$slow" <<< "$suites" || true; grep -v -E "$slow" <<< "$suites" || true) | sed '/^$/d')
mkdir -p sanitize-logs
run_suite() {
  local s=$1 t0 rc=0
  t0=$(date +%s)
  # A parametrized suite's name holds a slash (Examples/ExampleRuns): its log is Examples_ExampleRuns.log.
  ./vppdem_tests --gtest_filter="$s.*" > "sanitize-logs/${s//\//_}.log" 2>&1 || rc=$?
  printf '%-34s %6d s  %s\n' "$s" $(( $(date +%s) - t0 )) "$([ $rc -eq 0 ] && echo clean || echo "FAILED (rc $rc)")"
  return $rc
}
export -f run_suite
if [ -n "$ordered" ]; then
  xargs -P "$jobs" -I{} bash -c 'run_suite "$@"' _ {} <<< "$ordered" | tee sanitize-logs/table.txt || failed=1
fi
if [ $failed -ne 0 ]; then
  echo "sanitize.sh: FAILED (logs in build-sanitize/sanitize-logs/; the failing suites say FAILED above)" >&2
  exit 1
fi
echo "sanitize.sh: the suite ran clean under ASan and UBSan in $(( $(date +%s) - start )) s" >&2
