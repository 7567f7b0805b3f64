#!/usr/bin/env bash
# Regenerates the pictures of the docs (doc/img/) from the bundled samples and the SRTM fixture:
# previews drawn by `pyramid preview`. Run after scripts/demo.sh (it reads out/); commit the
# results when they change.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${PYRAMID_BUILD_DIR:-build}/cli
[ -f out/DEM.dat ] && [ -f out/ortho/RGB.dat ] && [ -f out/planet/DEM1.dat ] || bash scripts/demo.sh
"$bin/preprocessDem" ../shared/fixtures/inputs/mt_rainier_90m.tif -o out/rainier.dat -q
"$bin/pyramid" preview -q out/rainier.dat --size 400 -o doc/img/rainier-hillshade.png
"$bin/pyramid" preview -q out/rainier.dat --level 3 --style residuals -o doc/img/rainier-residuals.png
"$bin/pyramid" preview -q out/DEM.dat --size 400 -o doc/img/sample-dem-hillshade.png
"$bin/pyramid" preview -q out/ortho/RGB.dat --size 400 -o doc/img/sample-ortho.png
"$bin/pyramid" preview -q out/planet/DEM1.dat --projection world --size 800 --sea-level 590 --z-factor 20 --legend \
  -o doc/img/planet-world.png
"$bin/pyramid" preview -q out/planet/DEM1.dat --projection cube --size 800 --sea-level 590 --z-factor 20 \
  -o doc/img/planet-cube.png
"$bin/pyramid" preview -q out/planet/RGB1.dat --projection world --size 800 -o doc/img/planet-ortho.png
ls -l doc/img
