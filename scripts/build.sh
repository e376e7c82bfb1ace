#!/usr/bin/env bash
# Configures and builds vppdem (Release) into build/.
# usage: scripts/build.sh [TARGET ...]   (default: everything: the program, the tests, the Python
#        module and the benchmarks; the main job needs only the target vppdem)
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache (Debian's) where installed: the second and third builds of the CI (MPI, CUDA) and every
# rebuild take the objects that did not change from it; CCACHE_BASEDIR makes them shareable
# between build folders and checkouts.
launcher=()
if command -v ccache > /dev/null; then
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$(pwd)}
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" > /dev/null
if [ $# -gt 0 ]; then
  cmake --build build -j "$(nproc)" --target "$@"
else
  cmake --build build -j "$(nproc)"
fi
