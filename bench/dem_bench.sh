#!/usr/bin/env bash
# preprocessDem against GDAL's COG writer with LERC (the same error bound) on the same inputs:
# bits per input sample (ours with the default tiles and with --tile-size auto, GDAL's), the
# order-0 entropy of our residuals, wall time and peak RSS. A benchmark, run on demand (never a
# test); GDAL is only a peer here (and converts the matplotlib DEM), not a dependency.
#
#   bench/dem_bench.sh            results in $WORK (default /tmp/pyramid-dem-bench)
#
# Environment: BUILD (a Release build directory, configured here if missing; default
# build-release), WORK, SIZE (synthetic DEM side, default 8193), THREADS (default: all cores),
# REPEAT (runs per case, default 5: the median wall time is reported), SCALE (our --scale,
# default 1; GDAL's MAX_Z_ERROR is SCALE / 2, the same bound), SMALLEST_MAX (inputs of at most
# this many samples also run --compression smallest, whose Deflate level 12 is slow; default
# 20000000).
#
# Inputs:
# * real terrain: ../shared/fixtures/inputs/mt_rainier_90m.tif (an SRTM 3-arc-second tile,
#   1201 x 1201 int16) and jacksboro-dem.tif, the USGS DEM of the Jacksboro fault (Tennessee,
#   403 x 344 int16) that Debian's python-matplotlib-data ships as sample data (an .npz, turned
#   into a GeoTIFF here without numpy);
# * coasts (flat sea at 0 m, where LERC's constant blocks win): coast-900.tif, coast-1200.tif and
#   flooded-600/900/1200/1500.tif, made here from the Rainier tile (the land above 900 or 1200 m,
#   lowered to start at 0 m at the shore; or the heights below 600 to 1500 m flooded to 0 behind
#   cliffs), srtm-flooded-1500.tif (srtm-4097.tif below, its heights below 1500 m flooded), and
#   topobathy-sea0.tif, matplotlib's real topography-and-bathymetry sample (120 x 91, near
#   Vancouver Island) with the sea clamped to 0 m;
# * samples/dem.tif (385 x 385, from an 8-bit map: 39.2 m terraces) and srtm-4097.tif, a 641 x
#   641 cut of samples/srtm.png (the Himalaya, red x 10000 / 255 metres) upsampled to 4097 x 4097;
# * a deterministic synthetic SIZE x SIZE float32 DEM (bench/dem_synthetic_heights.cpp).
# preprocessDem runs on each with the default 192-tiles (resampled unless the input is 24 x 2^M
# + 1 samples a side) and with --tile-size auto (the input's own grid where one fits), the
# latter with each residual codec: deflate (the original tools' tiles), smallest (the smallest
# tiles the original runtime reads) and context (libpyramid's own). Our residuals' entropy
# comes from bench/dem_bench.c over the C API.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-dem-bench}
SIZE=${SIZE:-8193}
THREADS=${THREADS:-$(nproc)}
REPEAT=${REPEAT:-5}
SCALE=${SCALE:-1}
SMALLEST_MAX=${SMALLEST_MAX:-20000000}
MAX_Z_ERROR=$(awk -v s="$SCALE" 'BEGIN {print s / 2}')
RAINIER=$ROOT/../shared/fixtures/inputs/mt_rainier_90m.tif

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
need_bench_tools
need_package python3 python3-minimal
[ -f /usr/share/matplotlib/mpl-data/sample_data/jacksboro_fault_dem.npz ] ||
    as_root apt-get install -y python-matplotlib-data >/dev/null

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DPYRAMID_WITH_GL=OFF >/dev/null
fi
cmake --build "$BUILD" -j"$(nproc)" --target preprocessDem pyramid_runtime >/dev/null
DEM=$(find "$BUILD" -name preprocessDem -type f -perm -u+x | head -n 1)
RUNTIME=$(dirname "$(find "$BUILD" -name 'libpyramid-runtime.so' | head -n 1)")

mkdir -p "$WORK"
cd "$WORK"
cc -std=c99 -O2 -I"$ROOT" "$ROOT/bench/dem_bench.c" -o dem_bench -L"$RUNTIME" -lpyramid-runtime -lm -Wl,-rpath,"$RUNTIME"
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
INPUTS=()
if [ -f "$RAINIER" ]; then
    cp -f "$RAINIER" mt_rainier_90m.tif
    INPUTS+=(mt_rainier_90m.tif)
    # Coastal inputs made from the Rainier tile (no real coastal SRTM tile is at hand offline):
    # coast-L.tif = max(height - L, 0), a flat sea at 0 m meeting land that rises from the shore
    # as on a real coast (20 % of the area sea for L = 900, 46 % for 1200), and flooded-L.tif =
    # the heights below L set to 0, the same sea behind cliffs. The int16 samples go through
    # ENVI raw files (which keep the georeferencing) and Python without numpy.
    for made in coast-900 coast-1200 flooded-600 flooded-900 flooded-1200 flooded-1500; do
        if [ ! -f "$made.tif" ]; then
            gdal_translate -q -of ENVI mt_rainier_90m.tif "$made.raw"
            python3 - "$made.raw" "${made%-*}" "${made##*-}" <<'PY'
import array, sys
path, kind, level = sys.argv[1], sys.argv[2], int(sys.argv[3])
assert sys.byteorder == "little"
h = array.array("h", open(path, "rb").read())
if kind == "coast":
    h = array.array("h", (max(v - level, 0) for v in h))
else:
    h = array.array("h", (v if v >= level else 0 for v in h))
open(path, "wb").write(h.tobytes())
PY
            gdal_translate -q "$made.raw" "$made.part.tif"
            rm -f "$made.raw" "$made.hdr" "$made.raw.aux.xml"
            mv "$made.part.tif" "$made.tif"
        fi
        INPUTS+=("$made.tif")
    done
fi
# npz_to_tif NPZ ARRAY OUTPUT [sea0]: one array of a numpy .npz (C order; int16, or float32 with
# sea0) as an int16 GeoTIFF, through raw samples behind a GDAL VRT, read without numpy. sea0:
# the heights rounded and the sea (below 0) clamped to 0 m, as SRTM stores it.
npz_to_tif() {
    python3 - "$1" "$2" "$4" <<'PY'
import array, ast, sys, zipfile
npz, name, mode = sys.argv[1], sys.argv[2], sys.argv[3]
npy = zipfile.ZipFile(npz).read(name + ".npy")
length = int.from_bytes(npy[8:10], "little")
header = ast.literal_eval(npy[10:10 + length].decode("latin1"))
assert header["descr"] == ("<f4" if mode == "sea0" else "<i2") and not header["fortran_order"], header
rows, cols = header["shape"]
samples = npy[10 + length:]
if mode == "sea0":
    samples = array.array("h", (max(round(v), 0) for v in array.array("f", samples))).tobytes()
open("npz.raw", "wb").write(samples)
open("npz.vrt", "w").write(
    f'<VRTDataset rasterXSize="{cols}" rasterYSize="{rows}"><VRTRasterBand dataType="Int16" band="1" '
    f'subClass="VRTRawRasterBand"><SourceFilename relativetoVRT="1">npz.raw</SourceFilename>'
    f'<ByteOrder>LSB</ByteOrder><ImageOffset>0</ImageOffset><PixelOffset>2</PixelOffset>'
    f'<LineOffset>{2 * cols}</LineOffset></VRTRasterBand></VRTDataset>\n')
PY
    gdal_translate -q npz.vrt "$3"
    rm -f npz.raw npz.vrt
}
SAMPLE_DATA=/usr/share/matplotlib/mpl-data/sample_data
# The Jacksboro DEM: elevation.npy, int16, row 0 = north.
[ -f jacksboro-dem.tif ] || npz_to_tif "$SAMPLE_DATA/jacksboro_fault_dem.npz" elevation jacksboro-dem.tif
# A real coast: topobathy.npz's topo.npy (topography and bathymetry, float32 metres, 91 x 120,
# row 0 = south, near Vancouver Island), the sea clamped to 0 m.
[ -f topobathy-sea0.tif ] || npz_to_tif "$SAMPLE_DATA/topobathy.npz" topo topobathy-sea0.tif sea0
# srtm-4097.tif's heights below 1500 m flooded to 0 (80 % of it): cliffs on smooth terrain.
if [ ! -f srtm-flooded-1500.tif ]; then
    gdal_translate -q -of ENVI srtm-4097.tif srtm-flooded.raw
    python3 - srtm-flooded.raw <<'PY'
import array, sys
assert sys.byteorder == "little"
h = array.array("f", open(sys.argv[1], "rb").read())
open(sys.argv[1], "wb").write(array.array("f", (v if v >= 1500 else 0.0 for v in h)).tobytes())
PY
    gdal_translate -q -co COMPRESS=DEFLATE -co PREDICTOR=3 -co TILED=YES srtm-flooded.raw srtm-flooded-1500.part.tif
    rm -f srtm-flooded.raw srtm-flooded.hdr srtm-flooded.raw.aux.xml
    mv srtm-flooded-1500.part.tif srtm-flooded-1500.tif
fi
INPUTS+=(jacksboro-dem.tif topobathy-sea0.tif dem.tif srtm-4097.tif srtm-flooded-1500.tif "synthetic-$SIZE.tif")

RESULTS=$WORK/results.tsv
printf 'input\tvariant\twall_s\tpeak_rss_mb\tbytes\tinput_samples\tmax_error\ttile\tresiduals\tentropy\ttile_bytes\n' >"$RESULTS"

# run INPUT VARIANT OUTPUT COMMAND...: wall time (the median of $REPEAT runs, timed in
# nanoseconds around the command), peak RSS (the largest of the runs, from /usr/bin/time),
# bytes of OUTPUT and, for ours, the tiles chosen and the residuals' statistics (dem_bench).
run() {
    local input=$1 variant=$2 output=$3
    shift 3
    BEFORE_RUN="rm -f '$output' report.json" timed_runs "$REPEAT" "$@"
    local wall=$WALL_S rss=$PEAK_RSS_MB bytes samples error=- tile=- residuals=- entropy=- tile_bytes=-
    bytes=$(stat -c %s "$output")
    samples=$(oiiotool --info -v "$input" | awk '/^'"$input"'/ {print $3 * $5; exit}')
    if [ -f report.json ]; then
        error=$(jq '[.levels[].max_error] | max' report.json)
        tile=$(jq -r '"\(.header.tile_size)/\(.header.tile_size / pow(2; .header.min_level))/\(.header.max_level)"' report.json)
        read -r residuals entropy tile_bytes _ < <(./dem_bench "$output")
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$input" "$variant" "$wall" "$rss" "$bytes" "$samples" \
        "$error" "$tile" "$residuals" "$entropy" "$tile_bytes" | tee -a "$RESULTS"
}

OURS=("$DEM" --quiet --threads "$THREADS" --scale "$SCALE" --report report.json)
COG=(gdal_translate -q -of COG -co COMPRESS=LERC_DEFLATE -co MAX_Z_ERROR="$MAX_Z_ERROR" -co OVERVIEWS=AUTO -co NUM_THREADS="$THREADS")

for input in "${INPUTS[@]}"; do
    run "$input" default DEM.dat "${OURS[@]}" "$input" -o DEM.dat
    run "$input" auto DEM.dat "${OURS[@]}" "$input" -o DEM.dat --tile-size auto
    samples=$(oiiotool --info -v "$input" | awk '/^'"$input"'/ {print $3 * $5; exit}')
    if [ "$samples" -le "$SMALLEST_MAX" ]; then
        run "$input" smallest DEM.dat "${OURS[@]}" "$input" -o DEM.dat --tile-size auto --compression smallest
    fi
    run "$input" context DEM.dat "${OURS[@]}" "$input" -o DEM.dat --tile-size auto --compression context
    run "$input" gdal cog.tif "${COG[@]}" "$input" cog.tif
done
rm -f DEM.dat cog.tif report.json

# The summaries: each preprocessDem run against the GDAL run on the same input.
echo
awk -F'\t' '
    NR == 1 { next }
    $2 == "gdal" { gwall[$1] = $3; grss[$1] = $4; gbytes[$1] = $5; next }
    { ours[++count] = $0 }
    END {
        printf "| input | tiles | ours s | GDAL s | ours/GDAL | ours RSS MB | GDAL RSS MB | ours max error |\n"
        printf "|---|---|---|---|---|---|---|---|\n"
        for (i = 1; i <= count; ++i) {
            split(ours[i], f, "\t")
            printf "| %s | %s %s | %.3f | %.3f | %.2f | %d | %d | %s |\n", f[1], f[2], f[8], f[3], gwall[f[1]], f[3] / gwall[f[1]], f[4], grss[f[1]], f[7]
        }
    }' "$RESULTS"
echo
awk -F'\t' '
    NR == 1 { next }
    { samples[$1] = $6; if (!($1 in seen)) { seen[$1] = 1; order[++count] = $1 } }
    $2 == "gdal" { gbits[$1] = 8 * $5 / $6; next }
    { bits[$1, $2] = 8 * $5 / $6; tile[$1, $2] = $8; ent[$1, $2] = $9 * $10 / $6; h[$1, $2] = $10; coded[$1, $2] = 8 * $11 / ($9 * $10) }
    function cell(v) { return v == "" ? "-" : sprintf("%.3f", v) }
    function ratio(a, b) { return a == "" ? "-" : sprintf("%.2f", a / b) }
    END {
        printf "| input | samples | default tiles | ours default | auto tiles | ours auto | smallest | context | GDAL LERC | default / GDAL | auto / GDAL | smallest / GDAL | context / GDAL | entropy (auto) | Deflate / entropy | context / entropy | entropy per residual |\n"
        printf "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
        for (i = 1; i <= count; ++i) {
            n = order[i]
            printf "| %s | %d | %s | %.3f | %s | %.3f | %s | %s | %.3f | %.2f | %.2f | %s | %s | %.3f | %.2f | %.2f | %.3f |\n", n, samples[n], tile[n, "default"], bits[n, "default"], tile[n, "auto"], bits[n, "auto"], cell(bits[n, "smallest"]), cell(bits[n, "context"]), gbits[n], bits[n, "default"] / gbits[n], bits[n, "auto"] / gbits[n], ratio(bits[n, "smallest"], gbits[n]), ratio(bits[n, "context"], gbits[n]), ent[n, "auto"], coded[n, "auto"], coded[n, "context"], h[n, "auto"]
        }
    }' "$RESULTS"
echo
echo "bits per input sample. tiles: tile size/root tile size/maxLevel. smallest and context: the auto"
echo "tiles with --compression smallest and context. entropy: the order-0 entropy of the auto pyramid's"
echo "stored residuals (dem_bench.c), in bits per input sample; Deflate / entropy and context / entropy:"
echo "the tiles' bytes against it. raw figures: $RESULTS"
