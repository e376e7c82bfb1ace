#!/usr/bin/env bash
# The test suite under AddressSanitizer and UndefinedBehaviorSanitizer (issue 25): a separate
# build in build-sanitize/ (-DVPPDEM_SANITIZE=ON, no Python module: a sanitized extension needs
# the runtime preloaded into the interpreter; no benchmarks), then ctest; any report fails its
# test. Installs nothing: run the README's test command once first.
# usage: scripts/sanitize.sh [CTEST ARGS ...]   (e.g. -R 'Study|Damper' for a part)
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVPPDEM_SANITIZE=ON -DVPPDEM_PYTHON=OFF \
  -DVPPDEM_BENCHMARKS=OFF > /dev/null
cmake --build build-sanitize -j "$(nproc)" --target vppdem vppdem_tests
cd build-sanitize
# detect_leaks: a leak is a report too; abort_on_error gives a core-free, nonzero exit.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
start=$(date +%s)
ctest --output-on-failure -j "$(nproc)" -E 'python|Python' "$@"
echo "sanitize.sh: the suite ran clean under ASan and UBSan in $(( $(date +%s) - start )) s" >&2
