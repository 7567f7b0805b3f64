#!/usr/bin/env bash
# Regenerates the pictures of the docs (doc/img/) from the bundled samples and the SRTM fixture:
# previews drawn by `pyramid preview`. Run after scripts/demo.sh (it reads out/); commit the
# results when they change.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${PYRAMID_BUILD_DIR:-build}/cli
[ -f out/DEM.dat ] && [ -f out/ortho/RGB.dat ] || bash scripts/demo.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/preprocessDem" ../shared/fixtures/inputs/mt_rainier_90m.tif -o "$work/rainier.dat" -q
"$bin/pyramid" preview -q "$work/rainier.dat" --size 400 -o doc/img/rainier-hillshade.png
"$bin/pyramid" preview -q "$work/rainier.dat" --level 3 --style residuals -o doc/img/rainier-residuals.png
"$bin/pyramid" preview -q out/DEM.dat --size 400 -o doc/img/sample-dem-hillshade.png
"$bin/pyramid" preview -q out/ortho/RGB.dat --size 400 -o doc/img/sample-ortho.png
ls -l doc/img
