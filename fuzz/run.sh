#!/bin/sh
# Runs every fuzz target for SECONDS (default 60) seeded with the broken-file corpus and the
# original tools' files. New inputs go to BUILD/fuzz-work/TARGET; crashes to BUILD/fuzz-work/.
# A libFuzzer run uses one core: as many targets run at once as there are cores, each still for
# SECONDS, and their reports are printed in order once they are done.
# Usage: fuzz/run.sh BUILD_DIR [SECONDS]   (BUILD_DIR configured with -DPYRAMID_BUILD_FUZZERS=ON)
set -eu
build=$(cd "$1" && pwd)
seconds=${2:-60}
src=$(cd "$(dirname "$0")/.." && pwd)
corpus=$src/tests/corpus
work=$build/fuzz-work
cores=$(nproc 2>/dev/null || echo 1)
started=""
running=0

run() {
    target=$1
    shift
    mkdir -p "$work/$target"
    # libFuzzer takes seed folders, not files: the original files are copied into the work folder.
    for f in "$@"; do
        [ -f "$f" ] && cp "$f" "$work/$target/"
    done
    if [ "$running" -ge "$cores" ]; then
        wait
        running=0
    fi
    (cd "$work" && "$build/fuzz/$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 "$work/$target" "$corpus/valid") >"$work/$target.log" 2>&1 &
    running=$((running + 1))
    started="$started $target"
}

run residual_file_fuzz "$src/tests/data/proland/DEM.dat" "$src/tests/data/context/dem-levels-0-2.dat" "$corpus"/residual/*.dat
run ortho_file_fuzz "$src/tests/data/proland/RGB.dat" "$corpus"/ortho/*.dat
run tiff_tile_fuzz "$corpus"/tiff/*.tif "$corpus"/context/*.pyrc "$corpus"/valid/context-3.pyrc
run dxt_tile_fuzz "$corpus"/dxt/*.bin
run raster_input_fuzz "$corpus"/input/* "$corpus"/tiff/*.tif
wait
for target in $started; do
    echo "== $target ($seconds s)"
    grep -E '^(stat::|==|Done|INFO: Seed|.*ERROR)' "$work/$target.log" || true
done
# Any finding fails the run (named, one per line).
found=$(ls "$work" | grep -E '^(crash|leak|timeout|oom)-' || true)
if [ -n "$found" ]; then
    echo "$found" | sed "s|^|$work/|"
    exit 1
fi
echo "no crash, leak, timeout or out-of-memory"
