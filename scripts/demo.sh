#!/usr/bin/env bash
# The demo: installs what is missing, builds, turns the sample data in samples/ into pyramids
# under out/, and verifies them.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
bin=${PYRAMID_BUILD_DIR:-build}/cli
mkdir -p out

echo "== preprocessDem: samples/dem.tif -> out/DEM.dat"
"$bin/preprocessDem" samples/dem.tif -o out/DEM.dat --report out/DEM.json
"$bin/pyramid" verify out/DEM.dat --source samples/dem.tif
"$bin/pyramid" check out/DEM.dat

echo "== preprocessOrtho: samples/bluemarble.png -> out/ortho/{RGB.dat,dxt/RGB.dat,residuals/RGB.dat}"
"$bin/preprocessOrtho" samples/bluemarble.png -o out/ortho --report out/ortho.json
"$bin/pyramid" verify out/ortho/RGB.dat --source samples/bluemarble.png
"$bin/pyramid" verify out/ortho/residuals/RGB.dat --source samples/bluemarble.png --colour-residuals
"$bin/pyramid" check out/ortho/dxt/RGB.dat
