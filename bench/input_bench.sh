#!/usr/bin/env bash
# preprocessDem's memory and time on the input layouts real DEMs ship in: the same synthetic
# heights as an uncompressed TIFF, tiled Deflate with the floating-point predictor (a COG's
# layout), LZW strips, Deflate strips of one row, one Deflate strip for the whole image,
# BigTIFF tiles, ESRI's ASCII grid and BIL, and a 16-bit PNG. A benchmark, run on demand (never
# a test).
#
#   bench/input_bench.sh          results in $WORK (default /tmp/pyramid-input-bench)
#
# Environment: BUILD (a Release build directory, configured here if missing; default
# build-release), WORK, SIZES (default "8193 16385"), THREADS (default: all cores), CACHE_MB
# (--cache-mb, default 256), PEER (another preprocessDem, e.g. an older build's: run on the same
# inputs, with the ratios printed), REPEAT (runs per case, default 1). The bound to hold: peak
# RSS at most 256 MB plus the cache, whatever the layout and size. Every output is compared
# with the uncompressed input's, byte for byte.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-input-bench}
SIZES=${SIZES:-8193 16385}
THREADS=${THREADS:-$(nproc)}
CACHE_MB=${CACHE_MB:-256}
REPEAT=${REPEAT:-1}
PEER=${PEER:-}

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
[ -x /usr/bin/time ] || need_package /usr/bin/time time
need_package oiiotool openimageio-tools

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DPYRAMID_WITH_GL=OFF -DPYRAMID_BUILD_BENCH=ON >/dev/null
fi
cmake --build "$BUILD" -j"$(nproc)" --target preprocessDem dem_synthetic_heights tiff_layouts >/dev/null
DEM=$BUILD/cli/preprocessDem

mkdir -p "$WORK"
cd "$WORK"
printf 'input\ttool\twall_s\tpeak_rss_mb\tsame_bytes\n' | tee results.tsv
for size in $SIZES; do
    [ -f "dem-$size.tif" ] || "$BUILD/bench/dem_synthetic_heights" "dem-$size.tif" "$size"
    for layout in tiled-deflate-p3 lzw-strips deflate-rows one-strip bigtiff-tiled; do
        [ -f "$layout-$size.tif" ] || "$BUILD/bench/tiff_layouts" "dem-$size.tif" "$layout-$size.tif" "$layout"
    done
    [ -f "ascii-grid-$size.asc" ] || "$BUILD/bench/tiff_layouts" "dem-$size.tif" "ascii-grid-$size.asc" ascii-grid
    [ -f "bil-$size.bil" ] || "$BUILD/bench/tiff_layouts" "dem-$size.tif" "bil-$size.bil" bil
    # Heights 0..4000 m as 16-bit values (x 0.0001 x 65535: about 6.5 per metre).
    [ -f "png16-$size.png" ] || oiiotool "dem-$size.tif" --mulc 0.0001 -d uint16 -o "png16-$size.png"
    for input in "dem-$size.tif" tiled-deflate-p3-$size.tif lzw-strips-$size.tif deflate-rows-$size.tif \
        one-strip-$size.tif bigtiff-tiled-$size.tif ascii-grid-$size.asc bil-$size.bil png16-$size.png; do
        for tool in ours peer; do
            program=$DEM
            if [ "$tool" = peer ]; then
                [ -n "$PEER" ] || continue
                program=$PEER
            fi
            BEFORE_RUN="rm -f out.dat" timed_runs "$REPEAT" "$program" "$input" -o out.dat --quiet \
                --threads "$THREADS" --cache-mb "$CACHE_MB"
            same=-
            case $input in
            png16-*) ;;
            dem-*) cp out.dat "reference-$size.dat" ;;
            *) cmp -s out.dat "reference-$size.dat" && same=yes || same=NO ;;
            esac
            printf '%s\t%s\t%s\t%s\t%s\n' "$input" "$tool" "$WALL_S" "$PEAK_RSS_MB" "$same" | tee -a results.tsv
        done
    done
done
if [ -n "$PEER" ]; then
    echo
    echo "ours / peer, per input: wall time and peak RSS"
    awk -F'\t' 'NR > 1 {w[$1 FS $2] = $3; r[$1 FS $2] = $4; if ($2 == "ours") order[++n] = $1}
        END {for (i = 1; i <= n; ++i) {k = order[i];
             printf "%-28s time %.2f  rss %.2f\n", k, w[k FS "ours"] / w[k FS "peer"], r[k FS "ours"] / r[k FS "peer"]}}' results.tsv
fi
