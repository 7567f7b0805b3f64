#!/usr/bin/env bash
# Runs the preprocessors of two builds on the demo's and the benchmarks' inputs and compares
# every file they write, byte for byte: a change that should leave the output alone (a
# restructuring, an optimisation) is checked with it.
#
#   bash scripts/compare-builds.sh OLD_BUILD NEW_BUILD [WORK]
#
# OLD_BUILD and NEW_BUILD are build directories (their programs in cli/; the benchmarks'
# input generators in bench/ when built with -DPYRAMID_BUILD_BENCH=ON, else the synthetic
# cases are skipped). WORK (default /tmp/pyramid-compare) holds the inputs and outputs. SIZE
# sets the synthetic inputs' side (default 2049 for the DEM, SIZE - 1 for the image).
# Prints one line per case, "same" (naming files only the new build writes) or "DIFFERENT",
# and exits 1 if any file of the old build differs or is missing.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
old=$(cd "$1" && pwd)
new=$(cd "$2" && pwd)
work=${3:-/tmp/pyramid-compare}
size=${SIZE:-2049}
mkdir -p "$work"
cd "$work"

inputs=()
[ -x "$new/bench/dem_synthetic_heights" ] && { [ -f dem-$size.tif ] || "$new/bench/dem_synthetic_heights" dem-$size.tif "$size"; }
[ -x "$new/bench/ortho_synthetic_image" ] && { [ -f image-$((size - 1)).tif ] || "$new/bench/ortho_synthetic_image" image-$((size - 1)).tif $((size - 1)); }
rainier=$root/../shared/fixtures/inputs/mt_rainier_90m.tif

failed=0
# compare NAME PROGRAM ARGS...: runs PROGRAM ARGS of both builds (OUT in ARGS becomes each
# build's output path) and compares the outputs.
compare() {
    local name=$1 program=$2
    shift 2
    local side
    for side in old new; do
        local bin=$old
        [ $side = new ] && bin=$new
        rm -rf "out-$side"
        mkdir -p "out-$side"
        local args=("${@//OUT/out-$side/o}")
        "$bin/cli/$program" "${args[@]}" --quiet >/dev/null
    done
    # Every file the old build wrote must be the same; files only the new one writes (a feature
    # added since, such as a georeference sidecar) are named.
    local f same=1 added=()
    while IFS= read -r f; do
        cmp -s "out-old/$f" "out-new/$f" || same=0
    done < <(cd out-old && find . -type f | sort)
    while IFS= read -r f; do
        [ -f "out-old/$f" ] || added+=("${f#./}")
    done < <(cd out-new && find . -type f | sort)
    if [ $same = 1 ]; then
        printf 'same       %s (%s files)%s\n' "$name" "$(find out-old -type f | wc -l)" \
            "${added:+; new: ${added[*]}}"
    else
        printf 'DIFFERENT  %s\n' "$name"
        failed=1
    fi
}

s=$root/samples
compare "demo: preprocessDem dem.tif" preprocessDem "$s/dem.tif" -o OUT.dat
compare "demo: preprocessOrtho bluemarble.png" preprocessOrtho "$s/bluemarble.png" -o OUT
compare "demo: preprocessSphericalDem srtm.png" preprocessSphericalDem "$s/srtm.png" -o OUT --height-scale 10000/255
compare "demo: preprocessSphericalOrtho bluemarble.png" preprocessSphericalOrtho "$s/bluemarble.png" -o OUT
compare "preprocessDem dem.tif, 1 thread" preprocessDem "$s/dem.tif" -o OUT.dat --threads 1
compare "preprocessDem dem.tif, --scale auto, 32-tiles" preprocessDem "$s/dem.tif" -o OUT.dat --scale auto --tile-size 32 --root-tile-size 4
compare "preprocessOrtho bluemarble.png, TIFF only (single pass), 1 thread" preprocessOrtho "$s/bluemarble.png" -o OUT --outputs tiff --threads 1
compare "preprocessOrtho bluemarble.png, stretched 64-tiles" preprocessOrtho "$s/bluemarble.png" -o OUT --stretch --tile-size 64
compare "preprocessOrtho bluemarble.png, JPEG, DXT quality 2" preprocessOrtho "$s/bluemarble.png" -o OUT --compression jpeg --dxt-quality 2
compare "preprocessSphericalOrtho bluemarble.png, 64-tiles, TIFF only" preprocessSphericalOrtho "$s/bluemarble.png" -o OUT --tile-size 64 --outputs tiff
if [ -f "$rainier" ]; then
    compare "preprocessDem mt_rainier_90m.tif" preprocessDem "$rainier" -o OUT.dat
fi
if [ -f dem-$size.tif ]; then
    compare "preprocessDem synthetic $size" preprocessDem dem-$size.tif -o OUT.dat
    compare "preprocessDem synthetic $size, 128-tiles" preprocessDem dem-$size.tif -o OUT.dat --tile-size 128 --root-tile-size 16
fi
if [ -f image-$((size - 1)).tif ]; then
    compare "preprocessOrtho synthetic $((size - 1)), 256-tiles" preprocessOrtho image-$((size - 1)).tif -o OUT --tile-size 256
    compare "preprocessOrtho synthetic $((size - 1)), TIFF only" preprocessOrtho image-$((size - 1)).tif -o OUT --tile-size 256 --outputs tiff
fi
exit $failed
