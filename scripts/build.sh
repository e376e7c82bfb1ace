#!/usr/bin/env bash
# Configures and builds vppdem (Release) into build/.
# usage: scripts/build.sh [TARGET ...]   (default: everything: the program, the tests, the Python
#        module and the benchmarks; the main job needs only the target vppdem)
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
if [ $# -gt 0 ]; then
  cmake --build build -j "$(nproc)" --target "$@"
else
  cmake --build build -j "$(nproc)"
fi
