#!/usr/bin/env bash
# The spherical preprocessors on a synthetic global map, against GDAL doing a comparable job on
# the same input and cores: wall time, peak RSS and bytes. A benchmark, run on demand (never a
# test); GDAL is only a peer here, not a dependency.
#
#   bench/sphere_bench.sh          results in $WORK (default /tmp/pyramid-sphere-bench)
#
# Environment: BUILD (a Release build directory, configured here if missing; default
# build-release), WORK, WIDTH (of the global map, default 16384; the height is half), THREADS
# (default: all cores).
#
# Inputs: a deterministic WIDTH x WIDTH/2 float32 height map (bench/dem_synthetic_heights.cpp)
# and an RGB image (bench/ortho_synthetic_image.cpp), read as global equirectangular maps.
#
# Ours: preprocessSphericalDem --scale 1 (error <= 0.5 m) and preprocessSphericalOrtho (lossless
# TIFF tiles only, the job comparable with GDAL's; then all three outputs, with the DXT and
# colour-residual files), six faces each, WGS84, default levels: a face is at least WIDTH / 4
# cells across (6144 for 16384 with the default tile sizes).
#
# GDAL's comparable job: reproject the map onto the six faces of a cube (gdalwarp, bilinear,
# gnomonic projection about each face centre, i.e. the cube's own central projection, on a
# sphere) at the same face size, each written as a COG with overviews: LERC_DEFLATE with
# MAX_Z_ERROR=0.5 for heights, DEFLATE for imagery. The jobs differ in detail (our files hold
# every level's tiles with borders, DXT and colour-residual variants for imagery), not in kind.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-sphere-bench}
WIDTH=${WIDTH:-16384}
HEIGHT=$((WIDTH / 2))
THREADS=${THREADS:-$(nproc)}

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
need_bench_tools
need_package gdalwarp gdal-bin

build_programs preprocessSphericalDem preprocessSphericalOrtho
SDEM=$(program_path preprocessSphericalDem)
SORTHO=$(program_path preprocessSphericalOrtho)

mkdir -p "$WORK"
cd "$WORK"
heights=heights-${WIDTH}x$HEIGHT.tif
image=image-${WIDTH}x$HEIGHT.tif
if [ ! -f "$heights" ]; then
    g++ -std=c++20 -O2 "$ROOT/bench/dem_synthetic_heights.cpp" -o dem_synthetic_heights -lOpenImageIO -lOpenImageIO_Util
    ./dem_synthetic_heights "part-$heights" "${WIDTH}x$HEIGHT"
    mv "part-$heights" "$heights"
fi
if [ ! -f "$image" ]; then
    g++ -std=c++20 -O2 "$ROOT/bench/ortho_synthetic_image.cpp" -o ortho_synthetic_image -lOpenImageIO -lOpenImageIO_Util
    ./ortho_synthetic_image "part-$image" "${WIDTH}x$HEIGHT"
    mv "part-$image" "$image"
fi
# GDAL needs the maps' georeferencing: pixel-is-area over the whole globe, as ours reads them.
for map in "$heights" "$image"; do
    gdal_translate -q -of VRT -a_srs EPSG:4326 -a_ullr -180 90 180 -90 "$map" "${map%.tif}.vrt"
done

RESULTS=$WORK/results.tsv
printf 'case\ttool\twall_s\tpeak_rss_mb\tbytes\tface_side\n' >"$RESULTS"

# run CASE TOOL OUTPUT_DIR SIDE COMMAND...: time and peak RSS of COMMAND, bytes under OUTPUT_DIR.
run() {
    local case=$1 tool=$2 out=$3 side=$4
    shift 4
    BEFORE_RUN="rm -rf '$out'" timed_runs 1 "$@"
    local wall=$WALL_S rss=$PEAK_RSS_MB bytes
    bytes=$(du -sb "$out" | cut -f1)
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$case" "$tool" "$wall" "$rss" "$bytes" "$side" | tee -a "$RESULTS"
}

# GDAL on six faces, one after the other, in one timed shell. Face centres as ours: 1 north
# pole, 2..5 on the equator at 90 W, 0, 90 E, 180, 6 south pole.
gdal_faces() { # MAP.vrt OUT SIDE CREATION-OPTIONS...
    local map=$1 out=$2 side=$3
    shift 3
    mkdir -p "$out"
    local R=6371008.8 face=1
    for centre in "+lat_0=90 +lon_0=0" "+lat_0=0 +lon_0=-90" "+lat_0=0 +lon_0=0" "+lat_0=0 +lon_0=90" \
        "+lat_0=0 +lon_0=180" "+lat_0=-90 +lon_0=0"; do
        gdalwarp -q -overwrite -t_srs "+proj=gnom $centre +R=$R +units=m" -te -$R -$R $R $R -ts "$side" "$side" \
            -r bilinear -multi -wo NUM_THREADS="$THREADS" -of COG "$@" -co NUM_THREADS="$THREADS" \
            -co OVERVIEWS=AUTO "$map" "$out/face$face.tif"
        face=$((face + 1))
    done
}
export -f gdal_faces

# The face size ours chooses by default: the first 24 << M >= WIDTH / 4.
m=0
while [ $((24 << m)) -lt $((WIDTH / 4)) ]; do m=$((m + 1)); done
dem_side=$(((24 << m) + 1))
m=0
while [ $((192 << m)) -lt $((WIDTH / 4)) ]; do m=$((m + 1)); done
ortho_side=$((192 << m))

run "dem ${WIDTH}x$HEIGHT" ours planet-dem "$dem_side" "$SDEM" "$heights" -o planet-dem --threads "$THREADS" --scale 1 --quiet --report dem-report.json
run "dem ${WIDTH}x$HEIGHT" gdal gdal-dem "$dem_side" bash -c "gdal_faces ${heights%.tif}.vrt gdal-dem $dem_side -co COMPRESS=LERC_DEFLATE -co MAX_Z_ERROR=0.5"
run "ortho ${WIDTH}x$HEIGHT" ours planet-ortho "$ortho_side" "$SORTHO" "$image" -o planet-ortho --threads "$THREADS" --quiet --outputs tiff
run "ortho ${WIDTH}x$HEIGHT, all outputs" ours planet-ortho "$ortho_side" "$SORTHO" "$image" -o planet-ortho --threads "$THREADS" --quiet --report ortho-report.json
run "ortho ${WIDTH}x$HEIGHT" gdal gdal-ortho "$ortho_side" bash -c "gdal_faces ${image%.tif}.vrt gdal-ortho $ortho_side -co COMPRESS=DEFLATE"
echo "our largest DEM error: $(jq '[.faces[].dem.levels[].max_error] | max' dem-report.json) m (bound 0.5)"
rm -rf planet-dem planet-ortho gdal-dem gdal-ortho

echo
awk -F'\t' '
    NR == 1 { next }
    $2 == "gdal" { gwall[$1] = $3; grss[$1] = $4; gbytes[$1] = $5; next }
    { ours[++count] = $0 }
    END {
        printf "| case | face side | ours s | GDAL s | ours/GDAL | ours RSS MB | GDAL RSS MB | ours bytes | GDAL bytes |\n"
        printf "|---|---|---|---|---|---|---|---|---|\n"
        for (i = 1; i <= count; ++i) {
            split(ours[i], f, "\t"); peer = f[1]; sub(/, all outputs$/, "", peer)
            printf "| %s | %s | %.1f | %.1f | %.2f | %d | %d | %d | %d |\n", f[1], f[6], f[3], gwall[peer], f[3] / gwall[peer], f[4], grss[peer], f[5], gbytes[peer]
        }
    }' "$RESULTS"
echo
echo "raw figures: $RESULTS"
