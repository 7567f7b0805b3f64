#!/usr/bin/env bash
# Configures and builds libpyramid into build/ (or $PYRAMID_BUILD_DIR).
# Extra arguments go to CMake's configure step, e.g. -DPYRAMID_SANITIZE=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${PYRAMID_BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=${PYRAMID_BUILD_TYPE:-RelWithDebInfo} "$@" >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
