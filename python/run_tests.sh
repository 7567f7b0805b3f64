#!/bin/sh
# The Python package's tests against an installed copy: installs BUILD_DIR into a temporary
# prefix (cmake --install), the package into the same prefix (pip, offline, with the system's
# setuptools), then runs python/tests/ with pytest from outside the source tree, so that
# `import libpyramid` is the installed copy and finds the libraries through its prefix.
#
# Usage: run_tests.sh BUILD_DIR [PYTEST_ARGS...]
#        run_tests.sh --prefix PREFIX [PYTEST_ARGS...]   (a copy installed already; pip adds to it)
# PYTHON names the interpreter (default: python3). Without python3, numpy or pytest the tests
# are skipped (exit 77, ctest's SKIP_RETURN_CODE), unless PYRAMID_REQUIRE_PYTHON=1 (CI), where
# that is a failure.
set -eu
if [ "$1" = --prefix ]; then
  build=""
  prefix=$(cd "$2" && pwd)
  shift 2
else
  build=$(cd "$1" && pwd)
  shift
fi
here=$(cd "$(dirname "$0")" && pwd)

# missing PYTHON: what PYTHON lacks of the interpreter and modules the tests need ("" if none).
missing() {
  command -v "$1" >/dev/null 2>&1 || { echo " $1"; return; }
  for module in numpy pytest pip setuptools; do
    "$1" -c "import $module" 2>/dev/null || printf ' %s' "$module"
  done
}
# python3 on PATH, or the system's when that one lacks the modules (a user's own interpreter
# first on PATH).
python=${PYTHON:-python3}
missing=$(missing "$python")
if [ -n "$missing" ] && [ -z "${PYTHON:-}" ] && [ -x /usr/bin/python3 ] && [ -z "$(missing /usr/bin/python3)" ]; then
  python=/usr/bin/python3
  missing=""
fi
if [ -n "$missing" ]; then
  if [ "${PYRAMID_REQUIRE_PYTHON:-0}" = 1 ]; then
    echo "PYRAMID_REQUIRE_PYTHON=1 but missing:$missing (scripts/install-deps.sh installs them)" >&2
    exit 1
  fi
  echo "SKIPPED: the Python package's tests need$missing (scripts/install-deps.sh installs them)" >&2
  exit 77
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if [ -n "$build" ]; then
  prefix=$tmp/prefix
  cmake --install "$build" --prefix "$prefix" >/dev/null
fi
# pip builds from a copy: the source tree stays free of build/ and *.egg-info.
cp -R "$here" "$tmp/src"
rm -rf "$tmp/src/tests" "$tmp/src/build" "$tmp/src"/*.egg-info
"$python" -m pip install --quiet --no-build-isolation --no-index --no-deps --disable-pip-version-check --root-user-action=ignore \
  --prefix "$prefix" "$tmp/src"
# Where pip put it (lib/python3.X/site-packages, or Debian's local/lib/python3.X/dist-packages).
init=$(find "$prefix" -path '*/libpyramid/__init__.py' | head -n 1)
test -n "$init" || { echo "pip installed no libpyramid package under $prefix" >&2; exit 1; }
site=$(dirname "$(dirname "$init")")

cd "$tmp"
PYTHONPATH=$site PYRAMID_TEST_PREFIX=$prefix PYRAMID_TEST_SOURCE=$(dirname "$here") PYTHONDONTWRITEBYTECODE=1 \
  "$python" -m pytest -p no:cacheprovider -q --basetemp="$tmp/pytest" "$here/tests" "$@"
