#!/usr/bin/env bash
# The README's second command: install, build from scratch, run the quick tier of the tests
# (under 10 minutes on a fresh 2-core machine: docs/benchmarks.md, "The test command").
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
rm -rf build
bash scripts/build.sh
cd build
# The quick tier: every test but those labelled long (CMakeLists.txt, vppdem_long_tests), which
# .ci/run runs after this command (`ctest -L long`).
ctest --output-on-failure -j "$(nproc)" -LE long
