#!/usr/bin/env bash
# preprocessOrtho against GDAL's COG writer on the same inputs: wall time, peak RSS and bytes.
# A benchmark, run on demand (never a test); GDAL is only a peer here, not a dependency.
#
#   bench/ortho_bench.sh            results in $WORK (default /tmp/pyramid-ortho-bench)
#
# Environment: BUILD (a Release build directory, configured here if missing; default
# build-release), WORK, SIZE (synthetic image side, default 6144), THREADS (default: all cores),
# REPEAT (runs of each case compared with GDAL, default 3: the median wall time is reported;
# the cases without a GDAL counterpart run once), INPUTS (the inputs to run, default all four),
# LAYOUTS (the synthetic image's compressed copies whose default run is paired with GDAL too,
# default "tiled-deflate lzw-strips bigtiff-tiled jpeg-tiled"; empty for none).
#
# Inputs: a deterministic synthetic SIZE x SIZE RGB image (bench/ortho_synthetic_image.cpp),
# samples/bluemarble.png, a 5400x2700 upsampled copy of it, and a square 3072x3072 one (its
# western 675x675 pixels upsampled). On the synthetic image preprocessOrtho uses the tile size
# T <= 256 with T << maxLevel = SIZE (192 for 6144, 256 for 8192) so that its finest level is
# the input's pixels, as in the COG (no resampling, same pixel count apart from the 2-pixel tile
# borders); on the Blue Marble inputs it uses the default 192-pixel tiles: the 2:1 maps are
# resampled into the upper half of a 192 << maxLevel square (2.6 times GDAL's pixels), the
# square one is its finest level pixel for pixel (192 << 4 = 3072).
#
# Two tables: the TIFF cases (Deflate, JPEG) against GDAL's COG of the same compression, each
# the median of REPEAT runs; then each output alone (tiff, dxt, residuals) and the default run
# (all three), each run paired with a GDAL COG DEFLATE run of the same input (A B A B ...), with
# the median of the pairs' ratios, which holds when the shared machine's speed drifts.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-ortho-bench}
SIZE=${SIZE:-6144}
THREADS=${THREADS:-$(nproc)}
REPEAT=${REPEAT:-3}

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
need_bench_tools
need_package oiiotool openimageio-tools

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DPYRAMID_WITH_GL=OFF >/dev/null
fi
cmake --build "$BUILD" -j"$(nproc)" --target preprocessOrtho >/dev/null
ORTHO=$(find "$BUILD" -name preprocessOrtho -type f -perm -u+x | head -n 1)

mkdir -p "$WORK"
cd "$WORK"
if [ ! -f "synthetic-$SIZE.tif" ]; then
    g++ -std=c++20 -O2 "$ROOT/bench/ortho_synthetic_image.cpp" -o ortho_synthetic_image -lOpenImageIO -lOpenImageIO_Util
    ./ortho_synthetic_image "synthetic-$SIZE.part.tif" "$SIZE"
    mv "synthetic-$SIZE.part.tif" "synthetic-$SIZE.tif"
fi
cp -f "$ROOT/samples/bluemarble.png" bluemarble.png
[ -f bluemarble-5400.png ] || oiiotool bluemarble.png --resize 5400x2700 -o bluemarble-5400.png
[ -f bluemarble-3072.png ] || oiiotool bluemarble.png --cut 675x675+0+0 --resize 3072x3072 -o bluemarble-3072.png

INPUTS=${INPUTS:-synthetic-$SIZE.tif bluemarble.png bluemarble-5400.png bluemarble-3072.png}
# The synthetic image in the layouts real imagery ships in, written by GDAL (the peer): 256 x 256
# Deflate tiles with the horizontal predictor, LZW strips of 64 rows with it, the tiles as a
# BigTIFF, and 256 x 256 JPEG tiles in YCbCr (quality 90, as aerial imagery ships). Both tools
# decode them; ours through its block cache (--cache-mb, 256 MB).
LAYOUTS=${LAYOUTS-tiled-deflate lzw-strips bigtiff-tiled jpeg-tiled}
for layout in $LAYOUTS; do
    [ -f "synthetic-$SIZE-$layout.tif" ] && continue
    case $layout in
    tiled-deflate) options=(-co TILED=YES -co COMPRESS=DEFLATE -co PREDICTOR=2) ;;
    lzw-strips) options=(-co COMPRESS=LZW -co PREDICTOR=2 -co BLOCKYSIZE=64) ;;
    bigtiff-tiled) options=(-co BIGTIFF=YES -co TILED=YES -co COMPRESS=DEFLATE -co PREDICTOR=2) ;;
    jpeg-tiled) options=(-co TILED=YES -co COMPRESS=JPEG -co PHOTOMETRIC=YCBCR -co JPEG_QUALITY=90) ;;
    *) echo "LAYOUTS: unknown layout '$layout' (tiled-deflate, lzw-strips, bigtiff-tiled, jpeg-tiled)" >&2; exit 2 ;;
    esac
    gdal_translate -q "${options[@]}" "synthetic-$SIZE.tif" "synthetic-$SIZE-$layout.part.tif"
    mv "synthetic-$SIZE-$layout.part.tif" "synthetic-$SIZE-$layout.tif"
done
# The synthetic image's tile size: its side halved until at most 256 (a multiple of 4, for DXT).
SYNTHETIC_TILE=$SIZE
while [ "$SYNTHETIC_TILE" -gt 256 ] && [ $((SYNTHETIC_TILE % 2)) = 0 ]; do SYNTHETIC_TILE=$((SYNTHETIC_TILE / 2)); done
if [ "$SYNTHETIC_TILE" -gt 256 ] || [ $((SYNTHETIC_TILE % 4)) != 0 ]; then
    echo "SIZE=$SIZE: no tile size of at most 256 (a multiple of 4) makes its finest level" >&2
    exit 2
fi

RESULTS=$WORK/results.tsv
printf 'case\ttool\twall_s\tpeak_rss_mb\tbytes\ttiles\n' >"$RESULTS"

# run CASE TOOL OUTPUT COMMAND...: wall time of COMMAND (the median of RUNS runs, timed in
# nanoseconds around it), peak RSS (the largest, from /usr/bin/time), bytes of OUTPUT (file or dir).
RUNS=$REPEAT
run() {
    local case=$1 tool=$2 output=$3
    shift 3
    BEFORE_RUN="rm -rf '$output' report.json" timed_runs "$RUNS" "$@"
    local wall=$WALL_S rss=$PEAK_RSS_MB bytes tiles=-
    bytes=$(find "$output" -type f \( -name '*.dat' -o -name '*.tif' \) -printf '%s\n' | awk '{s += $1} END {print s}')
    [ -f report.json ] && [ "$tool" = ours ] && tiles=$(jq .tiles report.json)
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$case" "$tool" "$wall" "$rss" "$bytes" "$tiles" | tee -a "$RESULTS"
}

OURS=("$ORTHO" --quiet --threads "$THREADS" --report report.json)
COG=(gdal_translate -q -of COG -co OVERVIEWS=AUTO -co NUM_THREADS="$THREADS")

# tile_args INPUT: the --tile-size of INPUT (none: the default 192).
tile_args() { [ "$1" = "synthetic-$SIZE.tif" ] && echo "--tile-size $SYNTHETIC_TILE"; true; }

for input in $INPUTS; do
    read -r -a tile <<<"$(tile_args "$input")"
    RUNS=$REPEAT
    run "$input deflate" ours out-ours "${OURS[@]}" "$input" -o out-ours --outputs tiff "${tile[@]}"
    run "$input deflate" gdal out-cog.tif "${COG[@]}" -co COMPRESS=DEFLATE "$input" out-cog.tif
    run "$input jpeg90" ours out-ours "${OURS[@]}" "$input" -o out-ours --outputs tiff --compression jpeg --jpeg-quality 90 "${tile[@]}"
    run "$input jpeg90" gdal out-cog.tif "${COG[@]}" -co COMPRESS=JPEG -co QUALITY=90 "$input" out-cog.tif
    # GDAL's JPEG tiles are YCbCr 4:2:0 (its default for RGB): the like-for-like comparison.
    run "$input jpeg90-ycbcr" ours out-ours "${OURS[@]}" "$input" -o out-ours --outputs tiff --compression jpeg-ycbcr --jpeg-quality 90 "${tile[@]}"
    RUNS=1
    run "$input levels-only" ours out-ours "${OURS[@]}" "$input" -o out-ours --outputs tiff --compression none "${tile[@]}"
done

# paired INPUT LABEL ARGS...: REPEAT runs of preprocessOrtho INPUT ARGS, each followed by a GDAL
# COG DEFLATE run of INPUT; one line of PAIRED: the median wall times, the median of the pairs'
# ratios, our peak RSS, bytes and tiles.
PAIRED=$WORK/paired.tsv
printf 'input\toutputs\tours_s\tgdal_s\tratio\tours_rss_mb\tbytes\ttiles\ttile_pixels\n' >"$PAIRED"
paired() {
    local input=$1 label=$2 k ours=() gdal=() ratios=() rss=0 bytes tiles side
    shift 2
    for ((k = 0; k < REPEAT; ++k)); do
        BEFORE_RUN="rm -rf out-ours report.json" timed_runs 1 "${OURS[@]}" "$input" -o out-ours "$@"
        ours+=("$WALL_S")
        rss=$((PEAK_RSS_MB > rss ? PEAK_RSS_MB : rss))
        BEFORE_RUN="rm -f out-cog.tif" timed_runs 1 "${COG[@]}" -co COMPRESS=DEFLATE "$input" out-cog.tif
        gdal+=("$WALL_S")
        ratios+=("$(awk -v a="${ours[k]}" -v b="$WALL_S" 'BEGIN {printf "%.3f", a / b}')")
    done
    bytes=$(find out-ours -type f -name '*.dat' -printf '%s\n' | awk '{s += $1} END {print s}')
    tiles=$(jq .tiles report.json)
    side=$(($(jq .tile_size report.json) + 4))
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$input" "$label" "$(median "${ours[@]}")" "$(median "${gdal[@]}")" \
        "$(median "${ratios[@]}")" "$rss" "$bytes" "$tiles" $((side * side)) | tee -a "$PAIRED"
}

for input in $INPUTS; do
    read -r -a tile <<<"$(tile_args "$input")"
    paired "$input" tiff --outputs tiff "${tile[@]}"
    paired "$input" dxt --outputs dxt "${tile[@]}"
    paired "$input" residuals --outputs residuals "${tile[@]}"
    paired "$input" all-three "${tile[@]}"
done
for layout in $LAYOUTS; do
    paired "synthetic-$SIZE-$layout.tif" all-three --tile-size "$SYNTHETIC_TILE"
done
rm -rf out-ours out-cog.tif

# The summary: ours/GDAL wall-time ratios, and DXT throughput (tiles with their borders).
echo
awk -F'\t' '
    # The GDAL run a case of ours is compared with: the same case, "-ycbcr" variants included.
    function peer(c,    base) { base = c; sub(/-ycbcr$/, "", base); return base SUBSEP "gdal" }
    NR == 1 { next }
    {
        key = $1 SUBSEP $2; wall[key] = $3; rss[key] = $4; bytes[key] = $5; tiles[key] = $6
        if (!($1 in seen)) { seen[$1] = 1; order[++count] = $1 }
    }
    END {
        printf "| case | ours s | GDAL s | ours/GDAL | ours RSS MB | GDAL RSS MB | ours bytes | GDAL bytes |\n"
        printf "|---|---|---|---|---|---|---|---|\n"
        for (i = 1; i <= count; ++i) {
            c = order[i]; o = c SUBSEP "ours"; g = peer(c)
            if (!(g in wall)) continue
            printf "| %s | %.2f | %.2f | %.2f | %d | %d | %d | %d |\n", c, wall[o], wall[g], wall[o] / wall[g], rss[o], rss[g], bytes[o], bytes[g]
        }
        printf "\n| case (ours only) | s | RSS MB | bytes | tiles | tiles/s | Mpixel/s |\n|---|---|---|---|---|---|---|\n"
        for (i = 1; i <= count; ++i) {
            c = order[i]; o = c SUBSEP "ours"
            if (peer(c) in wall) continue
            side = c ~ /^synthetic/ ? synthetic : 196
            printf "| %s | %.2f | %d | %d | %d | %.0f | %.1f |\n", c, wall[o], rss[o], bytes[o], tiles[o], tiles[o] / wall[o], tiles[o] * side * side / wall[o] / 1e6
        }
    }' synthetic=$((SYNTHETIC_TILE + 4)) "$RESULTS"
echo
# Each output alone and all three, against GDAL COG DEFLATE of the same input, paired.
awk -F'\t' '
    NR == 1 { next }
    {
        if (!($1 in seen)) { seen[$1] = 1; order[++count] = $1 }
        line[$1, ++lines[$1]] = sprintf("| %s | %s | %.2f | %.2f | %.2f | %.1f | %d | %d |", $1, $2, $3, $4, $5,
                                       $8 * $9 / $3 / 1e6, $6, $7)
    }
    END {
        printf "| input | outputs | ours s | GDAL DEFLATE s | ours/GDAL (median of pairs) | Mpixel/s | ours RSS MB | ours bytes |\n"
        printf "|---|---|---|---|---|---|---|---|\n"
        for (i = 1; i <= count; ++i) for (k = 1; k <= lines[order[i]]; ++k) print line[order[i], k]
    }' "$PAIRED"
echo
echo "raw figures: $RESULTS, $PAIRED"
