#!/usr/bin/env bash
# The README's second command: install, build from scratch, run the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
rm -rf build
bash scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc)"
