#!/usr/bin/env bash
# The demo: installs what is missing, builds, turns the sample data in samples/ into pyramids
# under out/ (planar, then the six faces of a planet), and verifies them.
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

echo "== previews: out/DEM.png (hillshade), out/DEM-residuals.png, out/ortho.png"
"$bin/pyramid" preview out/DEM.dat -o out/DEM.png
"$bin/pyramid" preview out/DEM.dat --style residuals -o out/DEM-residuals.png
"$bin/pyramid" preview out/ortho/RGB.dat -o out/ortho.png

echo "== preprocessAperture: out/DEM.dat (its 384 intervals span about 10,000 km) -> out/APERTURE.dat, out/aperture.png"
"$bin/preprocessAperture" out/DEM.dat --size 1e7 -o out/APERTURE.dat
"$bin/pyramid" check out/APERTURE.dat
"$bin/pyramid" preview out/APERTURE.dat -o out/aperture.png

echo "== preprocessSphericalDem: samples/srtm.png (height = red x 10000/255 m) -> out/planet/DEM1..6.dat"
"$bin/preprocessSphericalDem" samples/srtm.png -o out/planet --height-scale 10000/255 --report out/planet-dem.json
echo "== preprocessSphericalOrtho: samples/bluemarble.png -> out/planet/{RGB1..6.dat,dxt/,residuals/}"
"$bin/preprocessSphericalOrtho" samples/bluemarble.png -o out/planet --report out/planet-ortho.json
"$bin/pyramid" verify out/planet --source samples/srtm.png --height-scale 10000/255 -q | tail -n 1
"$bin/pyramid" verify out/planet --name RGB --source samples/bluemarble.png -q | tail -n 1
"$bin/pyramid" verify out/planet/residuals --source samples/bluemarble.png --colour-residuals -q | tail -n 1
"$bin/pyramid" check out/planet | tail -n 1
echo "== preprocessSphericalAperture: out/planet/DEM1..6.dat -> out/planet-aperture/APERTURE1..6.dat"
"$bin/preprocessSphericalAperture" out/planet -o out/planet-aperture --directions 8 --radius 8

echo "== previews: out/planet-dem.png (world map; the map's sea, red 14 or 15, is 590 m), out/planet-cube.png, out/planet.png"
"$bin/pyramid" preview out/planet/DEM1.dat --projection world --sea-level 590 --z-factor 20 --legend -o out/planet-dem.png
"$bin/pyramid" preview out/planet/DEM1.dat --projection cube --sea-level 590 --z-factor 20 -o out/planet-cube.png
"$bin/pyramid" preview out/planet/RGB1.dat --projection world -o out/planet.png
