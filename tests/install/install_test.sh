#!/bin/sh
# Installs a build into a temporary prefix and builds two loaders against that copy alone, one
# with find_package(libpyramid COMPONENTS runtime), one with pkg-config; both read
# tests/data through the C API. The installed runtime library must need none of the
# preprocessors' or the GL producers' libraries.
# Usage: install_test.sh BUILD_DIR DATA_DIR [C_COMPILER]
set -eu
build=$1
data=$2
cc=${3:-cc}
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix

cmake --install "$build" --prefix "$prefix" >/dev/null

lib=$(find "$prefix" -name 'libpyramid-runtime.so.*.*.*' | head -n 1)
test -n "$lib" || { echo "no installed libpyramid-runtime.so" >&2; exit 1; }
needed=$(readelf -d "$lib" | grep NEEDED)
echo "$needed"
if echo "$needed" | grep -E 'gomp|EGL|libGL|libOpenGL|png|Geographic|squish|stb|OpenImageIO'; then
  echo "the installed runtime library needs a library it must not" >&2
  exit 1
fi
readelf -d "$lib" | grep -q 'SONAME.*libpyramid-runtime\.so\.' || { echo "no soname" >&2; exit 1; }
# Only the C API is exported.
others=$(nm -D --defined-only "$lib" | awk '{print $3}' | grep -v '^pyramid_' || true)
if [ -n "$others" ]; then
  echo "exports other than the C API:" >&2
  echo "$others" | head >&2
  exit 1
fi

# CMake package.
cmake -S "$here" -B "$tmp/cmake" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_C_COMPILER="$cc" >/dev/null
cmake --build "$tmp/cmake" >/dev/null
"$tmp/cmake/consumer" "$data"

# pkg-config.
pcdir=$(dirname "$(find "$prefix" -name libpyramid-runtime.pc | head -n 1)")
flags=$(PKG_CONFIG_PATH=$pcdir pkg-config --cflags --libs libpyramid-runtime)
libdir=$(PKG_CONFIG_PATH=$pcdir pkg-config --variable=libdir libpyramid-runtime)
# shellcheck disable=SC2086 # the flags are words
"$cc" -std=c99 -pedantic-errors -Wall -Wextra -o "$tmp/consumer-pc" "$here/consumer.c" $flags -Wl,-rpath,"$libdir"
"$tmp/consumer-pc" "$data"
