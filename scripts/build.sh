#!/usr/bin/env bash
# Configures and builds libpyramid into build/ (or $PYRAMID_BUILD_DIR).
# Extra arguments go to CMake's configure step, e.g. -DPYRAMID_SANITIZE=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${PYRAMID_BUILD_DIR:-build}
# A new build folder uses Ninja (scripts/install-deps.sh installs it): one graph of every compile
# and link, where a library's objects need not wait for the links of the libraries below it, and
# no make process and dependency scan per target (the tests are a hundred targets). A folder
# configured before keeps its generator (CMake refuses a change); CMAKE_GENERATOR, when set, chooses.
if [ -z "${CMAKE_GENERATOR:-}" ] && [ ! -f "$build_dir/CMakeCache.txt" ] && command -v ninja >/dev/null; then
  export CMAKE_GENERATOR=Ninja
fi
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=${PYRAMID_BUILD_TYPE:-RelWithDebInfo} "$@" >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
