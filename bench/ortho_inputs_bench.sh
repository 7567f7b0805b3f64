#!/usr/bin/env bash
# preprocessOrtho's default run (TIFF tiles, DXT tiles and colour residuals) against GDAL's COG
# DEFLATE writer on a set of inputs not tuned on: smooth, noisy and real imagery (issue 52).
# A benchmark, run on demand (never a test); GDAL is only a peer here, not a dependency.
#
#   bench/ortho_inputs_bench.sh      results in $WORK (default /tmp/pyramid-ortho-inputs)
#
# Environment: BUILD (a Release build directory, configured here if missing; default
# build-release), ORTHO (a preprocessOrtho to time instead of BUILD's, e.g. an older build's),
# WORK, THREADS (default 2), REPEAT (pairs per input, default 5), INPUTS (the inputs to run,
# default all below), EXTRA (more preprocessOrtho options for every run).
#
# Inputs (made in $WORK once; network only through apt-get download, the packages unpacked with
# dpkg -x, nothing installed):
#   noisy-6144.tif          smooth gradients plus Gaussian noise of sigma 6 per sample, 6144^2
#                           (bench/ortho_synthetic_image.cpp, `noise 6`)
#   synthetic-6144.tif      the synthetic image of bench/ortho_bench.sh
#   bluemarble-6144x3072.tif  marble-qt-data's 2700 x 1350 Blue Marble upsampled (oiiotool
#                           --resize, smooth): the upper half of a 6144^2 quad
#   bluemarble-2700.tif, citylights-2700.tif  marble-qt-data's 2700 x 1350 composites at their
#                           own size (resampled onto 172-tiles, the upper half of a 2752^2 quad)
#   bluemarble-jpeg.jpg, citylights-jpeg.jpg  the same composites as shipped: baseline JPEG
#   moon-jpeg.jpg           stellarium-data's Moon (textures/moon_4k.jpg, 4096 x 2048 baseline JPEG: a
#                           lunar albedo map, grey with a constant tint), as shipped (256-tiles:
#                           4096 = 256 x 16, pixel for pixel). Added after the others had been
#                           tuned on, and not tuned on since
#   moon-jpeg-192           the same file with --tile-size 192, the original tools' tiles (resampled
#                           into the upper half of a 6144^2 quad: 2.25 times its pixels)
#   schagen-jpeg.jpg, clementine-jpeg.jpg  marble-qt-data's Schagen world map of 1689 (a painted
#                           map on paper) and Clementine Moon mosaic, 2700 x 1350 baseline JPEGs
#                           as shipped (172-tiles); milkyway-png.png stellarium-data's Milky Way
#                           (textures/milkyway.png, 2048 x 1024 RGBA PNG: 256-tiles, pixel for
#                           pixel). The three were added with the Moon's change of defaults, and
#                           not tuned on
#   pleiades-png.png        stellarium-data's Pleiades (nebulae/default/pleiades.png, 1024^2, a
#                           palette PNG: 256 colours), as shipped
#   bluemarble-planes.tif, bluemarble-palette.tif  bluemarble-2700 upsampled to 4096 x 2048,
#                           Deflate in 256^2 tiles: bands in separate planes, and 8-bit palette
#                           indices (libtiff-tools' tiffmedian). The three were added with the
#                           direct reading of their layouts (before: the image I/O module), and not
#                           tuned on
#   landsat-3072.tif        r-cran-stars' Landsat 7 scene (L7_ETMs.tif, 349 x 352, bands 3, 2, 1:
#                           true colour) repeated 9 x 9 and cut to 3072^2
#   landsat-352.tif         the same scene at its own size (176-tiles, pixel for pixel)
#   kodak-6144.tif          librust-tiff-dev's Kodak photos kodim02 and kodim07 (768 x 512)
#                           alternated in a 9 x 12 mosaic cut to 6144^2
# Every run takes the default tiles (--tile-size auto), which encode the 6144^2 and 3072^2 inputs
# pixel for pixel on 192-tiles, as the COG stores them.
# Every input but the shipped JPEGs and PNGs and the last two TIFFs is an uncompressed striped
# RGB TIFF; all are read by both tools from the page cache.
#
# One table: per input, REPEAT default runs each followed by a GDAL run (A B A B ...), the
# median wall times and the median of the pairs' ratios, our peak RSS and bytes, GDAL's bytes.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-ortho-inputs}
THREADS=${THREADS:-2}
REPEAT=${REPEAT:-5}
read -r -a EXTRA_ARGS <<<"${EXTRA:-}"

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
need_bench_tools
need_package oiiotool openimageio-tools
need_package tiffmedian libtiff-tools
if [ -z "${ORTHO:-}" ]; then
    build_programs preprocessOrtho
    ORTHO=$(program_path preprocessOrtho)
fi

mkdir -p "$WORK"
cd "$WORK"

# unpack PACKAGE: the Debian package's files under debs/PACKAGE (downloaded, not installed).
unpack() {
    [ -d "debs/$1" ] && return
    mkdir -p debs
    if ! ls debs/"$1"_*.deb >/dev/null 2>&1; then
        (cd debs && { apt-get download "$1" >/dev/null 2>&1 || { as_root apt-get update >/dev/null && apt-get download "$1" >/dev/null; }; })
    fi
    dpkg -x debs/"$1"_*.deb "debs/$1.part"
    mv "debs/$1.part" "debs/$1"
}
# make NAME COMMAND...: runs COMMAND (which writes NAME.part.tif) unless NAME.tif exists.
make_input() {
    local name=$1
    shift
    [ -f "$name.tif" ] && return
    "$@"
    mv "$name.part.tif" "$name.tif"
}
TIFF=(--compression none -d uint8)

if [ ! -x ortho_synthetic_image ]; then
    g++ -std=c++20 -O2 "$ROOT/bench/ortho_synthetic_image.cpp" -o ortho_synthetic_image -lOpenImageIO -lOpenImageIO_Util
fi
make_input noisy-6144 ./ortho_synthetic_image noisy-6144.part.tif 6144 noise 6
make_input synthetic-6144 ./ortho_synthetic_image synthetic-6144.part.tif 6144

unpack marble-qt-data
MARBLE=debs/marble-qt-data/usr/share/marble/data/maps/earth
make_input bluemarble-2700 oiiotool "$MARBLE/bluemarble/bluemarble.jpg" "${TIFF[@]}" -o bluemarble-2700.part.tif
make_input citylights-2700 oiiotool "$MARBLE/citylights/citylights.jpg" "${TIFF[@]}" -o citylights-2700.part.tif
make_input bluemarble-6144x3072 oiiotool bluemarble-2700.tif --resize 6144x3072 "${TIFF[@]}" -o bluemarble-6144x3072.part.tif
# The composites as the package ships them (baseline JPEG, 2700 x 1350): read as they are.
[ -f bluemarble-jpeg.jpg ] || cp "$MARBLE/bluemarble/bluemarble.jpg" bluemarble-jpeg.jpg
[ -f citylights-jpeg.jpg ] || cp "$MARBLE/citylights/citylights.jpg" citylights-jpeg.jpg
# Added after the others had been tuned on: a painted map of 1689 and the Moon's Clementine mosaic.
[ -f schagen-jpeg.jpg ] || cp "$MARBLE/schagen1689/schagen1689.jpg" schagen-jpeg.jpg
[ -f clementine-jpeg.jpg ] || cp "$MARBLE/../moon/clementine/clementine.jpg" clementine-jpeg.jpg

unpack stellarium-data
[ -f moon-jpeg.jpg ] || cp debs/stellarium-data/usr/share/stellarium/textures/moon_4k.jpg moon-jpeg.jpg
[ -f milkyway-png.png ] || cp debs/stellarium-data/usr/share/stellarium/textures/milkyway.png milkyway-png.png
# Added with their layouts' direct reading (not tuned on): a palette PNG, and the Blue Marble
# with its bands in separate planes and as palette indices (tiffmedian's 256 colours), both at
# 4096 x 2048 in Deflate tiles of 256^2.
[ -f pleiades-png.png ] || cp debs/stellarium-data/usr/share/stellarium/nebulae/default/pleiades.png pleiades-png.png
make_input bluemarble-planes oiiotool bluemarble-2700.tif --resize 4096x2048 -d uint8 --planarconfig separate \
    --compression zip --tile 256 256 -o bluemarble-planes.part.tif
bluemarble_palette() {
    oiiotool bluemarble-2700.tif --resize 4096x2048 "${TIFF[@]}" -o bluemarble-4096.tif
    tiffmedian bluemarble-4096.tif bluemarble-median.tif
    tiffcp -c zip -t -w 256 -l 256 bluemarble-median.tif bluemarble-palette.part.tif
    rm bluemarble-4096.tif bluemarble-median.tif
}
make_input bluemarble-palette bluemarble_palette

unpack r-cran-stars
LANDSAT=debs/r-cran-stars/usr/lib/R/site-library/stars/tif/L7_ETMs.tif
# Bands 3, 2, 1 (red, green, blue) of the 6-band scene, as an RGB TIFF.
make_input landsat-352 oiiotool "$LANDSAT" --ch 2,1,0 "${TIFF[@]}" -o landsat-352.part.tif
mosaic() { # mosaic COLUMNSxROWS OUTPUT IMAGE...: the images repeated in a grid, in turn
    local grid=$1 output=$2 k=0 cells
    shift 2
    cells=$((${grid%x*} * ${grid#*x}))
    local list=()
    for ((k = 0; k < cells; ++k)); do list+=("${@:$((k % $# + 1)):1}"); done
    oiiotool "${list[@]}" --mosaic "$grid" "${TIFF[@]}" -o "$output"
}
landsat_3072() {
    mosaic 9x9 landsat-mosaic.tif landsat-352.tif
    oiiotool landsat-mosaic.tif --cut 3072x3072+0+0 "${TIFF[@]}" -o landsat-3072.part.tif
    rm landsat-mosaic.tif
}
make_input landsat-3072 landsat_3072

unpack librust-tiff-dev
KODAK=debs/librust-tiff-dev/usr/share/cargo/registry/tiff-0.7.3/tests/benches
# kodim02 and kodim07 alternate along each row and from row to row (9 columns: odd, so the
# next row starts with the other photo), cut to 6144^2.
kodak_6144() {
    mosaic 9x12 kodak-mosaic.tif "$KODAK/kodim02-lzw.tif" "$KODAK/kodim07-lzw.tif"
    oiiotool kodak-mosaic.tif --cut 6144x6144+0+0 "${TIFF[@]}" -o kodak-6144.part.tif
    rm kodak-mosaic.tif
}
make_input kodak-6144 kodak_6144

INPUTS=${INPUTS:-noisy-6144 bluemarble-6144x3072 synthetic-6144 kodak-6144 landsat-3072 bluemarble-2700 citylights-2700 landsat-352 bluemarble-jpeg citylights-jpeg moon-jpeg moon-jpeg-192 schagen-jpeg clementine-jpeg milkyway-png pleiades-png bluemarble-planes bluemarble-palette}
# input NAME: the file of input NAME (NAME.jpg or NAME.png for the shipped images, moon-jpeg.jpg for
# moon-jpeg-192, else NAME.tif).
input() { if [ "$1" = moon-jpeg-192 ]; then echo moon-jpeg.jpg; elif [ -f "$1.jpg" ]; then echo "$1.jpg"; elif [ -f "$1.png" ]; then echo "$1.png"; else echo "$1.tif"; fi; }
# tile_args NAME: the options of input NAME beyond the defaults.
tile_args() { case $1 in moon-jpeg-192) echo "--tile-size 192" ;; esac; }

OURS=("$ORTHO" --quiet --threads "$THREADS" --report report.json)
COG=(gdal_translate -q -of COG -co COMPRESS=DEFLATE -co OVERVIEWS=AUTO -co NUM_THREADS="$THREADS")

RESULTS=$WORK/results.tsv
printf 'input\tours_s\tgdal_s\tratio\tours_rss_mb\tours_bytes\tgdal_bytes\n' >"$RESULTS"
for name in $INPUTS; do
    read -r -a tile <<<"$(tile_args "$name")"
    [ "$REPEAT" -gt 0 ] || continue
    PAIR_A=("${OURS[@]}" "$(input "$name")" -o out-ours "${tile[@]}" "${EXTRA_ARGS[@]}") PAIR_A_CLEAN="rm -rf out-ours report.json"
    PAIR_B=("${COG[@]}" "$(input "$name")" out-cog.tif) PAIR_B_CLEAN="rm -f out-cog.tif"
    paired_runs "$REPEAT"
    bytes=$(find out-ours -type f -name '*.dat' -printf '%s\n' | awk '{s += $1} END {print s}')
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$A_S" "$B_S" "$RATIO" "$A_RSS_MB" "$bytes" \
        "$(stat -c %s out-cog.tif)" | tee -a "$RESULTS"
done
rm -rf out-ours out-cog.tif
markdown_table "$RESULTS" 'input|ours s|GDAL s|ours/GDAL (median of pairs)|ours RSS MB|ours bytes|GDAL bytes' '| %s | %.2f | %.2f | **%.2f** | %d | %d | %d |\n'
