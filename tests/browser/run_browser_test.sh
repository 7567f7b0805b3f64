#!/bin/sh
# The viewer in a real browser, against `pyramid serve` of this build: a cone DEM
# (make_cone.py, preprocessDem) served with `pyramid serve --port 0`, the page loaded by
# Debian's headless chromium (browser_test.py: its status element, the browser's network and
# console events, screenshots of the hillshade).
#
# Usage: run_browser_test.sh BUILD_DIR [OUT_DIR]
# Without chromium the test is skipped (exit 77, ctest's SKIP_RETURN_CODE), unless
# PYRAMID_REQUIRE_BROWSER=1 (CI), where that is a failure.
set -eu
build=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
if ! command -v chromium >/dev/null 2>&1; then
  if [ "${PYRAMID_REQUIRE_BROWSER:-0}" = 1 ]; then
    echo "PYRAMID_REQUIRE_BROWSER=1 but chromium is missing (scripts/install-deps.sh installs it)" >&2
    exit 1
  fi
  echo "SKIPPED: the browser test needs chromium (scripts/install-deps.sh installs it)" >&2
  exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=${2:-$tmp/shots}
/usr/bin/python3 "$here/make_cone.py" "$tmp/cone.tif"
"$build/cli/preprocessDem" "$tmp/cone.tif" -o "$tmp/cone/DEM.dat" --scale 0.05 -q
/usr/bin/python3 "$here/browser_test.py" --out "$out" \
  --serve "'$build/cli/pyramid' serve '$tmp/cone/DEM.dat' --port 0 --viewer-dir '$build/viewer' -q"
