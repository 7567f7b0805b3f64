#!/usr/bin/env bash
# Sparse sets against the dense layout (doc/format.md 1.5, "Sparse sets"): bytes written, wall
# time and peak RSS of preprocessSphericalDem and preprocessSphericalOrtho on small, fine maps
# that reach a little of the planet. A benchmark, run on demand (never a test). The inputs are made here with GDAL's Python
# bindings (a benchmark's peer tools, not a dependency), deterministic, besides the real SRTM tile
# of ../shared/fixtures (or tests/data).
#
#   bench/sparse_bench.sh          results in $WORK (default /tmp/pyramid-sparse-bench)
#
# Environment: BUILD (a Release build directory, configured here if missing; default
# build-release), WORK, THREADS (default: all cores), DENSE (1: also run --layout dense, which
# writes gigabytes for the first input; default 1), DENSE_ORTHO (1: also the imagery with --layout
# dense, which writes about 25 GB for the hillshade; default 0).
#
# Inputs:
#   elev-512.tif   512 x 512 float32 heights, EPSG:3857, 9 m pixels at 47.6 N (6 m on the ground):
#                  level 16 of the default 192-tiles
#   island.tif     1201 x 1201 int16, EPSG:4326, 1/1200 degree (an SRTM 1-degree tile of sea
#                  (0) with an island of a few pixels, at 10 N 110 W): level 13
#   rainier.tif    the real SRTM tile of Mount Rainier (1201 x 1201 int16, 90 m): level 13
#   base-and-rainier/  a 720 x 360 float32 global base (0.5 degree: level 3) and the Rainier tile, one
#                  mosaic (the directory): level 13 over the tile, level 3 elsewhere (sparse only:
#                  dense resamples the base at 90 m over the planet)
#   planar/       a 1000 x 1000 float32 base of 30 m and a 2000 x 2000 inset of 1 m in it, UTM 10N:
#                  preprocessDem of the mosaic (levels of the base's 30 m where it alone is, the
#                  inset's 1 m over the inset; before, the base was resampled at 1 m: 30000^2 samples)
#   shade-1024.tif 1024 x 1024 8-bit hillshade, EPSG:3857, 9.5 m pixels at 47.6 N: ortho level 13
#   alpha-1223.tif 1223 x 1223 RGBA (a disc, transparent around it), EPSG:3857, 4 m pixels at
#                  48.9 N: ortho level 14
#   ortho-planet/  a 2048 x 1024 global RGB base (level 5) and a 4096 x 4096 RGB inset of 1 arc-second
#                  (level 11): preprocessSphericalOrtho of the mosaic
#   ortho-planar/  a 1000 x 1000 RGB base of 30 m and a 2000 x 2000 RGB inset of 1 m, UTM 10N:
#                  preprocessOrtho of the mosaic (levels 3 and 8)
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -m "${BUILD:-$ROOT/build-release}")
WORK=${WORK:-/tmp/pyramid-sparse-bench}
THREADS=${THREADS:-$(nproc)}
DENSE=${DENSE:-1}

# shellcheck source=bench/common.sh
source "$ROOT/bench/common.sh"
need_bench_tools
/usr/bin/python3 -c 'import numpy, osgeo' 2>/dev/null || { as_root apt-get install -y python3-numpy python3-gdal >/dev/null; }

build_programs preprocessSphericalDem preprocessSphericalOrtho preprocessDem preprocessOrtho pyramid
PDEM=$(program_path preprocessDem)
SDEM=$(program_path preprocessSphericalDem)
SORTHO=$(program_path preprocessSphericalOrtho)
PORTHO=$(program_path preprocessOrtho)
PYR=$(program_path pyramid)

mkdir -p "$WORK"
cd "$WORK"
rainier="$ROOT/../shared/fixtures/inputs/mt_rainier_90m.tif"
[ -f "$rainier" ] || { echo "sparse_bench.sh: $rainier is missing" >&2; exit 1; }
cp "$rainier" rainier.tif
/usr/bin/python3 - <<'PY'
import numpy as np
from osgeo import gdal, osr

def write(path, arr, gt, epsg, dtype, nodata=None):
    h, w = arr.shape
    ds = gdal.GetDriverByName('GTiff').Create(path, w, h, 1, dtype, options=['COMPRESS=DEFLATE', 'TILED=YES'])
    ds.SetGeoTransform(gt)
    s = osr.SpatialReference()
    s.ImportFromEPSG(epsg)
    ds.SetProjection(s.ExportToWkt())
    band = ds.GetRasterBand(1)
    if nodata is not None:
        band.SetNoDataValue(nodata)
    band.WriteArray(arr)
    ds = None

rng = np.random.default_rng(1)
y, x = np.mgrid[0:512, 0:512].astype(np.float32)
z = 300 + 80 * np.sin(x / 37.0) * np.cos(y / 53.0) + 0.02 * (x - 256) ** 2 + rng.normal(0, 1.5, (512, 512))
write('elev-512.tif', z.astype(np.float32), (-13610000, 9.0, 0, 6040000, 0, -9.0), 3857, gdal.GDT_Float32)
y, x = np.mgrid[0:1201, 0:1201]
r2 = (x - 700.0) ** 2 + (y - 400.0) ** 2
island = np.where(r2 < 16, (400 - 20 * r2).clip(1, None), 0).astype(np.int16)
write('island.tif', island, (-110.0004167, 1 / 1200, 0, 10.0004167, 0, -1 / 1200), 4326, gdal.GDT_Int16)
y, x = np.mgrid[0:360, 0:720].astype(np.float64)
lat, lon = 90 - (y + 0.5) * 0.5, -180 + (x + 0.5) * 0.5
base = 1500 * np.cos(np.radians(lat)) ** 2 * np.sin(np.radians(3 * lon)) + 800
write('base-720.tif', base.astype(np.float32), (-180, 0.5, 0, 90, 0, -0.5), 4326, gdal.GDT_Float32)

def write_bands(path, bands, gt, epsg):
    h, w = bands[0].shape
    ds = gdal.GetDriverByName('GTiff').Create(path, w, h, len(bands), gdal.GDT_Byte,
                                              options=['COMPRESS=DEFLATE', 'TILED=YES'] + (['ALPHA=YES'] if len(bands) == 4 else []))
    ds.SetGeoTransform(gt)
    s = osr.SpatialReference()
    s.ImportFromEPSG(epsg)
    ds.SetProjection(s.ExportToWkt())
    for i, b in enumerate(bands):
        ds.GetRasterBand(i + 1).WriteArray(b)
    ds = None

import os
os.makedirs('planar', exist_ok=True)
y, x = np.mgrid[0:1000, 0:1000].astype(np.float64)
base = 600 + 300 * np.sin(x / 70.0) * np.cos(y / 90.0) + rng.normal(0, 3, (1000, 1000))
write('planar/base-30m.tif', base.astype(np.float32), (500000, 30, 0, 5230000, 0, -30), 32610, gdal.GDT_Float32)
y, x = np.mgrid[0:2000, 0:2000].astype(np.float64)
inset = 900 + 40 * np.sin(x / 37.0) * np.cos(y / 53.0) + rng.normal(0, 0.3, (2000, 2000))
write('planar/inset-1m.tif', inset.astype(np.float32), (514000, 1, 0, 5216000, 0, -1), 32610, gdal.GDT_Float32)

rng = np.random.default_rng(2)
y, x = np.mgrid[0:1024, 0:1024].astype(np.float32)
z = 300 + 80 * np.sin(x / 37.0) * np.cos(y / 53.0) + 0.02 * (x - 512) ** 2 + rng.normal(0, 1.5, (1024, 1024))
gy, gx = np.gradient(z)
shade = np.clip(0.5 + 0.5 * (-gx * 0.7 + gy * 0.7) / np.sqrt(1 + gx ** 2 + gy ** 2), 0, 1) * 254 + 1
write_bands('shade-1024.tif', [shade.astype(np.uint8)], (-13610000, 9.5, 0, 6040000, 0, -9.5), 3857)
y, x = np.mgrid[0:1223, 0:1223]
disc = np.where((x - 611) ** 2 + (y - 611) ** 2 < 600 ** 2, 255, 0).astype(np.uint8)
write_bands('alpha-1223.tif', [((x * 3) % 256).astype(np.uint8), ((y * 2) % 256).astype(np.uint8),
                               ((x + y) % 256).astype(np.uint8), disc], (261000, 4.0, 0, 6250000, 0, -4.0), 3857)

# Imagery of several resolutions: a global RGB base of 2048 x 1024 (0.176 degree: ortho level 5 of
# 192-pixel tiles) with a 4096 x 4096 inset of 1/3600 degree (level 11) at 46.5..47.6 N,
# 122.2..121.1 W; and a planar RGB base of 1000 x 1000 of 30 m with a 2000 x 2000 inset of 1 m
# (levels 3 and 8).
def colours(w, h, seed, scale):
    r = np.random.default_rng(seed)
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    return [np.clip(c + a * np.sin(x / (scale * p)) * np.cos(y / (scale * q)) + r.normal(0, 6, (h, w)), 0, 255).astype(np.uint8)
            for c, a, p, q in ((120, 70, 11, 17), (110, 60, 13, 7), (90, 50, 5, 19))]
os.makedirs('ortho-planet', exist_ok=True)
os.makedirs('ortho-planar', exist_ok=True)
write_bands('ortho-planet/base-global.tif', colours(2048, 1024, 3, 9.0), (-180, 360 / 2048, 0, 90, 0, -180 / 1024), 4326)
write_bands('ortho-planet/inset-1s.tif', colours(4096, 4096, 4, 4.0), (-122.2, 1 / 3600, 0, 47.6, 0, -1 / 3600), 4326)
write_bands('ortho-planar/base-30m.tif', colours(1000, 1000, 5, 6.0), (500000, 30, 0, 5230000, 0, -30), 32610)
write_bands('ortho-planar/inset-1m.tif', colours(2000, 2000, 6, 3.0), (514000, 1, 0, 5216000, 0, -1), 32610)
PY
mkdir -p base-and-rainier
cp base-720.tif rainier.tif base-and-rainier/

printf '| input | layout | bytes | files | wall s | peak RSS MB | verify (sparse) |\n|---|---|---|---|---|---|---|\n'
for input in elev-512.tif island.tif rainier.tif base-and-rainier; do
    for layout in sparse dense; do
        [ "$layout" = dense ] && [ "$DENSE" != 1 ] && continue
        [ "$input" = base-and-rainier ] && [ "$layout" = dense ] && continue # the base resampled at 90 m: terabytes
        out="out-${input%.tif}-$layout"
        BEFORE_RUN="rm -rf $out" timed_runs 1 "$SDEM" "$input" -o "$out" --layout "$layout" --threads "$THREADS" -q
        bytes=$(du -cb "$out"/*.dat | tail -n 1 | cut -f1)
        files=$(find "$out" -name '*.dat' | wc -l)
        verdict=-
        if [ "$layout" = sparse ]; then # a dense face of millions of empty tiles takes long to verify
            verdict=$("$PYR" verify "$out" --source "$input" >/dev/null 2>&1 && echo ok || echo FAILED)
        fi
        printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$input" "$layout" "$bytes" "$files" "$WALL_S" "$PEAK_RSS_MB" "$verdict"
        [ "$layout" = dense ] && rm -rf "$out"
    done
done

# A planar mosaic of two resolutions: the sparse default only (one resolution, the base at the
# inset's 1 m, would be 30000 x 30000 finest samples).
printf '\n| planar mosaic | layout | bytes | files | wall s | peak RSS MB | verify |\n|---|---|---|---|---|---|---|\n'
out=out-planar
BEFORE_RUN="rm -rf $out" timed_runs 1 "$PDEM" planar/base-30m.tif planar/inset-1m.tif -o "$out/DEM.dat" --threads "$THREADS" -q
bytes=$(find "$out" -name '*.dat' -printf '%s\n' | awk '{s += $1} END {print s}')
files=$(find "$out" -name '*.dat' | wc -l)
verdict=$("$PYR" verify "$out/DEM.dat" --source planar >/dev/null 2>&1 && echo ok || echo FAILED)
printf '| base 30 m + inset 1 m | sparse | %s | %s | %s | %s | %s |\n' "$bytes" "$files" "$WALL_S" "$PEAK_RSS_MB" "$verdict"

# Imagery: every output (TIFF, DXT, colour residuals); verify compares the TIFF tiles and the
# colours the colour-residual producer rebuilds with the map.
printf '\n| imagery | layout | bytes | files | wall s | peak RSS MB | verify (sparse) |\n|---|---|---|---|---|---|---|\n'
for input in shade-1024.tif alpha-1223.tif; do
    for layout in sparse dense; do
        [ "$layout" = dense ] && [ "${DENSE_ORTHO:-0}" != 1 ] && continue
        out="out-${input%.tif}-$layout"
        BEFORE_RUN="rm -rf $out" timed_runs 1 "$SORTHO" "$input" -o "$out" --layout "$layout" --threads "$THREADS" -q
        bytes=$(find "$out" -name '*.dat' -printf '%s\n' | awk '{s += $1} END {print s}')
        files=$(find "$out" -name '*.dat' | wc -l)
        verdict=-
        if [ "$layout" = sparse ]; then
            verdict=$("$PYR" verify "$out" --source "$input" >/dev/null 2>&1 &&
                "$PYR" verify "$out/residuals" --colour-residuals --source "$input" >/dev/null 2>&1 && echo ok || echo FAILED)
        fi
        printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$input" "$layout" "$bytes" "$files" "$WALL_S" "$PEAK_RSS_MB" "$verdict"
        [ "$layout" = dense ] && rm -rf "$out"
    done
done

# Imagery of several resolutions, sparse only (one resolution would sample the base at the inset's
# level everywhere: 6 x 4^11 tiles of the planet, 256 x 256 tiles of the plane).
printf '\n| imagery of several resolutions | bytes | files | wall s | peak RSS MB | verify |\n|---|---|---|---|---|---|\n'
out=out-ortho-planet
BEFORE_RUN="rm -rf $out" timed_runs 1 "$SORTHO" ortho-planet/base-global.tif ortho-planet/inset-1s.tif -o "$out" --threads "$THREADS" -q
bytes=$(find "$out" -name '*.dat' -printf '%s\n' | awk '{s += $1} END {print s}')
files=$(find "$out" -name '*.dat' | wc -l)
verdict=$("$PYR" verify "$out" --source ortho-planet >/dev/null 2>&1 &&
    "$PYR" verify "$out/residuals" --colour-residuals --source ortho-planet >/dev/null 2>&1 && echo ok || echo FAILED)
printf '| planet: global 0.18 degree + inset 1 arc-second | %s | %s | %s | %s | %s |\n' "$bytes" "$files" "$WALL_S" "$PEAK_RSS_MB" "$verdict"
out=out-ortho-planar
BEFORE_RUN="rm -rf $out" timed_runs 1 "$PORTHO" ortho-planar/base-30m.tif ortho-planar/inset-1m.tif -o "$out" --threads "$THREADS" -q
bytes=$(find "$out" -name '*.dat' -printf '%s\n' | awk '{s += $1} END {print s}')
files=$(find "$out" -name '*.dat' | wc -l)
verdict=$("$PYR" verify "$out/RGB.dat" --source ortho-planar >/dev/null 2>&1 &&
    "$PYR" verify "$out/residuals/RGB.dat" --colour-residuals --source ortho-planar >/dev/null 2>&1 && echo ok || echo FAILED)
printf '| plane: base 30 m + inset 1 m | %s | %s | %s | %s | %s |\n' "$bytes" "$files" "$WALL_S" "$PEAK_RSS_MB" "$verdict"
