#!/usr/bin/env bash
# preprocessOrtho's default run against GDAL's COG DEFLATE writer on one image in the containers
# imagery really comes in: uncompressed, Deflate, LZW, ZSTD, JPEG and WebP TIFFs, PNG, JPEG,
# 16-bit. The pixels are the same Blue Marble in every file (JPEG and WebP ones decoded as they
# are stored); what differs is how each tool reads them. A benchmark, run on demand (never a
# test); GDAL is only a peer and the maker of the TIFF variants here, not a dependency.
#
#   bench/ortho_formats_bench.sh      results in $WORK (default /tmp/pyramid-ortho-inputs)
#
# Environment: BUILD (a Release build directory, configured here if missing; default
# build-release), ORTHO (a preprocessOrtho to time instead of BUILD's), WORK, THREADS (default
# 2), REPEAT (pairs per file, default 5), FORMATS (the files to run, default all below).
#
# The image: bench/ortho_inputs_bench.sh's bluemarble-6144x3072.tif (marble-qt-data's 2700 x
# 1350 Blue Marble upsampled to 6144 x 3072), made first if missing. Variants, made once in
# $WORK/formats:
#   none.tif        uncompressed, striped (the image itself)
#   deflate.tif     Deflate, 256^2 tiles            lzw-pred.tif   LZW, horizontal predictor, strips
#   zstd.tif        ZSTD, 256^2 tiles               jpeg.tif       JPEG YCbCr, 256^2 tiles
#   webp.tif        WebP (lossy), 256^2 tiles       u16.tif        16-bit, Deflate, 256^2 tiles
#   image.png       PNG (oiiotool)                  image.jpg      baseline JPEG, quality 90 (oiiotool)
# One table: per file, REPEAT default runs each followed by a GDAL run (A B A B ...), the median
# wall times, the median of the pairs' ratios, and both tools' peak RSS.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-ortho-inputs}
THREADS=${THREADS:-2}
REPEAT=${REPEAT:-5}

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
need_bench_tools
need_package oiiotool openimageio-tools
if [ -z "${ORTHO:-}" ]; then
    build_programs preprocessOrtho
    ORTHO=$(program_path preprocessOrtho)
fi
[ -f "$WORK/bluemarble-6144x3072.tif" ] || INPUTS=bluemarble-6144x3072 REPEAT=0 bash "$ROOT/bench/ortho_inputs_bench.sh" >/dev/null
mkdir -p "$WORK/formats"
cd "$WORK/formats"
IMAGE=../bluemarble-6144x3072.tif

# variant FILE PART COMMAND...: runs COMMAND (which writes PART) unless FILE exists.
variant() {
    local file=$1 part=$2
    shift 2
    [ -f "$file" ] && return
    "$@"
    mv "$part" "$file"
    rm -f "$part.aux.xml"
}
gtiff() { gdal_translate -q -of GTiff "$@"; }
variant none.tif none.part.tif cp "$IMAGE" none.part.tif
variant deflate.tif deflate.part.tif gtiff -co COMPRESS=DEFLATE -co TILED=YES "$IMAGE" deflate.part.tif
variant lzw-pred.tif lzw-pred.part.tif gtiff -co COMPRESS=LZW -co PREDICTOR=2 "$IMAGE" lzw-pred.part.tif
variant zstd.tif zstd.part.tif gtiff -co COMPRESS=ZSTD -co TILED=YES "$IMAGE" zstd.part.tif
variant jpeg.tif jpeg.part.tif gtiff -co COMPRESS=JPEG -co PHOTOMETRIC=YCBCR -co TILED=YES "$IMAGE" jpeg.part.tif
variant webp.tif webp.part.tif gtiff -co COMPRESS=WEBP -co TILED=YES "$IMAGE" webp.part.tif
variant u16.tif u16.part.tif gtiff -ot UInt16 -scale 0 255 0 65535 -co COMPRESS=DEFLATE -co TILED=YES "$IMAGE" u16.part.tif
variant image.png image.part.png oiiotool "$IMAGE" -o image.part.png
variant image.jpg image.part.jpg oiiotool "$IMAGE" --compression jpeg:90 -o image.part.jpg

FORMATS=${FORMATS:-none.tif deflate.tif lzw-pred.tif zstd.tif jpeg.tif webp.tif u16.tif image.png image.jpg}
OURS=("$ORTHO" --quiet --threads "$THREADS")
COG=(gdal_translate -q -of COG -co COMPRESS=DEFLATE -co OVERVIEWS=AUTO -co NUM_THREADS="$THREADS")

RESULTS=$WORK/formats.tsv
printf 'file\tbytes\tours_s\tgdal_s\tratio\tours_rss_mb\tgdal_rss_mb\n' >"$RESULTS"
for file in $FORMATS; do
    [ "$REPEAT" -gt 0 ] || continue
    PAIR_A=("${OURS[@]}" "$file" -o out-ours) PAIR_A_CLEAN="rm -rf out-ours"
    PAIR_B=("${COG[@]}" "$file" out-cog.tif) PAIR_B_CLEAN="rm -f out-cog.tif"
    paired_runs "$REPEAT"
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$file" "$(stat -c %s "$file")" "$A_S" "$B_S" "$RATIO" "$A_RSS_MB" \
        "$B_RSS_MB" | tee -a "$RESULTS"
done
rm -rf out-ours out-cog.tif
markdown_table "$RESULTS" 'file|bytes|ours s|GDAL s|ours/GDAL (median of pairs)|ours RSS MB|GDAL RSS MB' '| %s | %d | %.2f | %.2f | **%.2f** | %d | %d |\n'
