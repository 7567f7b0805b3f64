#!/usr/bin/env bash
# A DEM build split across processes (doc/planet-scale.md) against the same build in one process,
# on this machine: one process with THREADS threads; mpirun with 1 rank; mpirun with 2 ranks of
# THREADS / 2 threads each; and the batch way, --part 0/2 and 1/2 one after the other, then
# `pyramid merge`. Wall time (median of REPEAT runs), peak RSS of the largest process, and a
# check that every way wrote the single run's bytes. A benchmark, run on demand (never a test).
#
#   bench/split_bench.sh            results in $WORK (default /tmp/pyramid-split-bench)
#
# Environment: BUILD (a Release build directory with MPI, configured here if missing; default
# build-release), WORK, SIZE (synthetic DEM side, default 8193), THREADS (default: all cores),
# REPEAT (default 3).
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-split-bench}
SIZE=${SIZE:-8193}
THREADS=${THREADS:-$(nproc)}
REPEAT=${REPEAT:-3}
HALF=$(( THREADS > 1 ? THREADS / 2 : 1 ))

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
[ -x /usr/bin/time ] || need_package /usr/bin/time time
need_package mpirun openmpi-bin
# Root may run mpirun only when it says so.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DPYRAMID_WITH_GL=OFF -DPYRAMID_WITH_MPI=ON >/dev/null
fi
cmake --build "$BUILD" -j"$(nproc)" --target preprocessDem pyramid >/dev/null
DEM=$(find "$BUILD" -name preprocessDem -type f -perm -u+x | head -n 1)
PYRAMID=$(find "$BUILD" -name pyramid -type f -perm -u+x | head -n 1)

mkdir -p "$WORK"
cd "$WORK"
if [ ! -f "synthetic-$SIZE.tif" ]; then
    g++ -std=c++20 -O2 "$ROOT/bench/dem_synthetic_heights.cpp" -o dem_synthetic_heights -lOpenImageIO -lOpenImageIO_Util
    ./dem_synthetic_heights "synthetic-$SIZE.part.tif" "$SIZE"
    mv "synthetic-$SIZE.part.tif" "synthetic-$SIZE.tif"
fi
IN=synthetic-$SIZE.tif
ARGS=(--quiet --scale 1 --tile-size 128 --root-tile-size 16)

RESULTS=$WORK/results.tsv
printf 'case\twall_s\tpeak_rss_mb\tsame_bytes\n' >"$RESULTS"
report() {
    local same=no
    cmp -s "$1" one/DEM.dat && same=yes
    printf '%s\t%s\t%s\t%s\n' "$2" "$WALL_S" "$PEAK_RSS_MB" "$same" | tee -a "$RESULTS"
}

BEFORE_RUN="rm -rf one" timed_runs "$REPEAT" "$DEM" "${ARGS[@]}" --threads "$THREADS" "$IN" -o one/DEM.dat
report one/DEM.dat "1 process, $THREADS threads"
BEFORE_RUN="rm -rf r1" timed_runs "$REPEAT" mpirun -n 1 "$DEM" "${ARGS[@]}" --threads "$THREADS" "$IN" -o r1/DEM.dat
report r1/DEM.dat "mpirun -n 1, $THREADS threads"
BEFORE_RUN="rm -rf r2" timed_runs "$REPEAT" mpirun -n 2 --oversubscribe "$DEM" "${ARGS[@]}" --threads "$HALF" "$IN" -o r2/DEM.dat
report r2/DEM.dat "mpirun -n 2, $HALF threads each"
cat >parts.sh <<SH
set -e
"$DEM" ${ARGS[*]} --threads $THREADS $IN -o p/DEM.dat --part 0/2
"$DEM" ${ARGS[*]} --threads $THREADS $IN -o p/DEM.dat --part 1/2
"$PYRAMID" merge -q p/DEM.dat.part-0-of-2 p/DEM.dat.part-1-of-2
SH
BEFORE_RUN="rm -rf p" timed_runs "$REPEAT" bash parts.sh
report p/DEM.dat "--part 0/2, 1/2 in turn, then merge"
mkdir -p m
"$DEM" "${ARGS[@]}" --threads "$THREADS" "$IN" -o m/DEM.dat --part 0/2
"$DEM" "${ARGS[@]}" --threads "$THREADS" "$IN" -o m/DEM.dat --part 1/2
BEFORE_RUN="rm -f m/DEM.dat" timed_runs "$REPEAT" "$PYRAMID" merge -q --keep-parts m/DEM.dat.part-0-of-2 m/DEM.dat.part-1-of-2
report m/DEM.dat "pyramid merge alone (2 parts)"
ls -l one/DEM.dat m/DEM.dat.part-* | awk '{print $5, $9}'
