#!/usr/bin/env bash
# preprocessDem against GDAL's COG writer with LERC (the same error bound) on the same inputs:
# wall time, peak RSS and bits per input sample. A benchmark, run on demand (never a test);
# GDAL is only a peer here, not a dependency.
#
#   bench/dem_bench.sh            results in $WORK (default /tmp/pyramid-dem-bench)
#
# Environment: BUILD (a Release build directory, configured here if missing; default
# build-release), WORK, SIZE (synthetic DEM side, default 8193), THREADS (default: all cores),
# REPEAT (runs per case, default 5: the median wall time is reported).
#
# Inputs: a deterministic synthetic SIZE x SIZE float32 DEM (bench/dem_synthetic_heights.cpp),
# the real one in samples/dem.tif, and a larger real-ish one: a 641 x 641 cut of samples/srtm.png
# (the Himalaya and the Tibetan plateau, red x 10000 / 255 metres) upsampled to 4097 x 4097. Both tools keep every sample within 0.5 m: preprocessDem
# --scale 1 (error <= scale/2) and LERC with MAX_Z_ERROR=0.5. preprocessDem runs twice on the
# synthetic DEM: with the default 192-tiles (the pyramid's finest level then has
# (24 << 9) + 1 = 12289 samples per side, resampled, 2.25 times the input's samples) and with
# 128-tiles and a 16-sample root, whose finest level is the input itself (16 << 9 = 8192).
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-dem-bench}
SIZE=${SIZE:-8193}
THREADS=${THREADS:-$(nproc)}
REPEAT=${REPEAT:-5}

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
need_bench_tools

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DPYRAMID_WITH_GL=OFF >/dev/null
fi
cmake --build "$BUILD" -j"$(nproc)" --target preprocessDem >/dev/null
DEM=$(find "$BUILD" -name preprocessDem -type f -perm -u+x | head -n 1)

mkdir -p "$WORK"
cd "$WORK"
if [ ! -f "synthetic-$SIZE.tif" ]; then
    g++ -std=c++20 -O2 "$ROOT/bench/dem_synthetic_heights.cpp" -o dem_synthetic_heights -lOpenImageIO -lOpenImageIO_Util
    ./dem_synthetic_heights "synthetic-$SIZE.part.tif" "$SIZE"
    mv "synthetic-$SIZE.part.tif" "synthetic-$SIZE.tif"
fi
cp -f "$ROOT/samples/dem.tif" dem.tif
if [ ! -f srtm-4097.tif ]; then
    oiiotool "$ROOT/samples/srtm.png" --ch R --cut 641x641+600+17 --resize 4097x4097 --mulc 10000 -d float -o srtm-4097.part.tif
    mv srtm-4097.part.tif srtm-4097.tif
fi

RESULTS=$WORK/results.tsv
printf 'case\ttool\twall_s\tpeak_rss_mb\tbytes\tinput_samples\tmax_error\n' >"$RESULTS"

# run CASE TOOL INPUT OUTPUT COMMAND...: wall time (the median of $REPEAT runs, timed in
# nanoseconds around the command), peak RSS (the largest of the runs, from /usr/bin/time) and
# bytes of OUTPUT.
run() {
    local case=$1 tool=$2 input=$3 output=$4
    shift 4
    BEFORE_RUN="rm -f '$output' report.json" timed_runs "$REPEAT" "$@"
    local wall=$WALL_S rss=$PEAK_RSS_MB bytes samples error=-
    bytes=$(stat -c %s "$output")
    samples=$(oiiotool --info -v "$input" | awk '/^'"$input"'/ {print $3 * $5; exit}')
    [ -f report.json ] && error=$(jq '[.levels[].max_error] | max' report.json)
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$case" "$tool" "$wall" "$rss" "$bytes" "$samples" "$error" | tee -a "$RESULTS"
}

OURS=("$DEM" --quiet --threads "$THREADS" --scale 1 --report report.json)
COG=(gdal_translate -q -of COG -co COMPRESS=LERC_DEFLATE -co MAX_Z_ERROR=0.5 -co OVERVIEWS=AUTO -co NUM_THREADS="$THREADS")

synthetic=synthetic-$SIZE.tif
run "$synthetic 192-tiles" ours "$synthetic" DEM.dat "${OURS[@]}" "$synthetic" -o DEM.dat
run "$synthetic 128-tiles" ours "$synthetic" DEM.dat "${OURS[@]}" "$synthetic" -o DEM.dat --tile-size 128 --root-tile-size 16
run "$synthetic" gdal "$synthetic" cog.tif "${COG[@]}" "$synthetic" cog.tif
run "dem.tif 192-tiles" ours dem.tif DEM.dat "${OURS[@]}" dem.tif -o DEM.dat
run "dem.tif" gdal dem.tif cog.tif "${COG[@]}" dem.tif cog.tif
run "srtm-4097.tif 192-tiles" ours srtm-4097.tif DEM.dat "${OURS[@]}" srtm-4097.tif -o DEM.dat
run "srtm-4097.tif" gdal srtm-4097.tif cog.tif "${COG[@]}" srtm-4097.tif cog.tif
rm -f DEM.dat cog.tif report.json

# The summary: each preprocessDem run against the GDAL run on the same input.
echo
awk -F'\t' '
    NR == 1 { next }
    $2 == "gdal" { gwall[$1] = $3; grss[$1] = $4; gbytes[$1] = $5; gbits[$1] = 8 * $5 / $6; next }
    { ours[++count] = $0 }
    END {
        printf "| case | ours s | GDAL s | ours/GDAL | ours RSS MB | GDAL RSS MB | ours bytes | GDAL bytes | ours bits/sample | GDAL bits/sample | ours max error |\n"
        printf "|---|---|---|---|---|---|---|---|---|---|---|\n"
        for (i = 1; i <= count; ++i) {
            split(ours[i], f, "\t"); input = f[1]; sub(/ [0-9]+-tiles$/, "", input)
            printf "| %s | %.3f | %.3f | %.2f | %d | %d | %d | %d | %.3f | %.3f | %s |\n", f[1], f[3], gwall[input], f[3] / gwall[input], f[4], grss[input], f[5], gbytes[input], 8 * f[5] / f[6], gbits[input], f[7]
        }
    }' "$RESULTS"
echo
echo "bits/sample: file bits per input sample. raw figures: $RESULTS"
