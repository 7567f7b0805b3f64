#!/usr/bin/env bash
# preprocessDem on a mosaic of many small GeoTIFFs against the same heights stitched into one
# file: wall time, peak RSS and the most file descriptors open at once, and whether the two
# pyramids are byte-identical (they must be). A benchmark, run on demand (never a test).
#
#   bench/mosaic_bench.sh          results in $WORK (default /tmp/pyramid-mosaic-bench)
#
# Environment: BUILD (a Release build directory, configured here if missing; default
# build-release), WORK, COLS x ROWS tiles (default 40 x 25: 1,000 tiles) of SIZE samples a side
# (default 256), THREADS (default: all cores), REPEAT (runs per case, default 3).
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-mosaic-bench}
COLS=${COLS:-40}
ROWS=${ROWS:-25}
SIZE=${SIZE:-256}
THREADS=${THREADS:-$(nproc)}
REPEAT=${REPEAT:-3}

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
[ -x /usr/bin/time ] || need_package /usr/bin/time time

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DPYRAMID_WITH_GL=OFF -DPYRAMID_BUILD_BENCH=ON >/dev/null
fi
cmake --build "$BUILD" -j"$(nproc)" --target preprocessDem mosaic_tiles >/dev/null
DEM=$BUILD/cli/preprocessDem

mkdir -p "$WORK/tiles"
cd "$WORK"
if [ ! -f tiles/whole.tif ]; then
    "$BUILD/bench/mosaic_tiles" tiles "$COLS" "$ROWS" "$SIZE"
fi
ls tiles/tile_*.tif > list.txt

# run NAME ARGS...: REPEAT runs; prints wall (median), peak RSS and peak descriptors.
run() {
    local name=$1
    shift
    local walls=() rss=0 fds=0 k
    for ((k = 0; k < REPEAT; ++k)); do
        rm -f "$name.dat"
        local start end
        start=$(date +%s%N)
        /usr/bin/time -f "%M" -o "$name.rss" "$DEM" "$@" -o "$name.dat" --threads "$THREADS" -q &
        local timer=$! pid="" n peak=0
        while kill -0 "$timer" 2>/dev/null; do
            pid=${pid:-$(pgrep -P "$timer" preprocessDem || true)}
            if [ -n "$pid" ]; then
                n=$(ls "/proc/$pid/fd" 2>/dev/null | wc -l || true)
                [ "$n" -gt "$peak" ] && peak=$n
            fi
            sleep 0.02
        done
        wait "$timer"
        end=$(date +%s%N)
        walls+=($(( (end - start) / 1000000 )))
        [ "$(cat "$name.rss")" -gt "$rss" ] && rss=$(cat "$name.rss")
        [ "$peak" -gt "$fds" ] && fds=$peak
    done
    local median
    median=$(printf '%s\n' "${walls[@]}" | sort -n | sed -n "$(( (REPEAT + 1) / 2 ))p")
    local files=1
    [ "$1" = --input-list ] && files=$(wc -l < "$2")
    printf '%s\t%d\t%.2f\t%d\t%d\n' "$name" "$files" "$(echo "$median / 1000" | bc -l)" $(( rss / 1024 )) "$fds"
    eval "WALL_$name=$median"
}

printf 'input\tfiles\twall_s\tpeak_rss_mb\tpeak_fds\n'
run stitched tiles/whole.tif
run mosaic --input-list list.txt
if cmp -s stitched.dat mosaic.dat; then same=yes; else same=NO; fi
printf 'mosaic / stitched wall: %.2f; byte-identical pyramids: %s\n' "$(echo "$WALL_mosaic / $WALL_stitched" | bc -l)" "$same"
