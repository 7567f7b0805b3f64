#!/usr/bin/env python3
"""A data-build pipeline with the libpyramid package (doc/python.md).

    python3 samples/python_pipeline.py OUT_DIR [INPUT.tif]

Without INPUT: heights made in numpy (a volcano on a slope) are encoded to OUT_DIR/DEM.dat, read
back, and every finest-level sample is checked within scale / 2 of the array. With INPUT (e.g.
an SRTM GeoTIFF such as mt_rainier_90m.tif): the installed preprocessDem encodes it, and the
height at the root quad's centre (by longitude and latitude when the input is geographic) is
checked against the finest level's sample there.
Then a hillshade-like ortho pyramid is made from the heights (OUT_DIR/ortho/), and a summary
printed. Exits 1 with a one-line message when a check fails.
"""

import sys
from pathlib import Path

import numpy as np

import libpyramid


def volcano(side=513):
    """Heights in metres, row 0 north: a cone with a crater on a gentle slope."""
    y, x = np.mgrid[0:side, 0:side].astype(np.float32) / (side - 1)
    r = np.hypot(x - 0.55, y - 0.45)
    cone = 2400 * np.exp(-(r / 0.18) ** 2) - 500 * np.exp(-(r / 0.03) ** 2)
    return (300 + 400 * x + cone).astype(np.float32)


def shade(heights):
    """An 8-bit grey hillshade of a height array (light from the north-west)."""
    gy, gx = np.gradient(heights.astype(np.float64))
    lit = (-gx + gy) / np.sqrt(1 + gx * gx + gy * gy) / np.sqrt(2)
    return np.clip(128 + 127 * lit * 8, 0, 255).astype(np.uint8)


def finest_grid(dem):
    """The finest level's elevations assembled north up, as the encoder's input was."""
    level, n = dem.levels[-1], dem.tile_size
    grid = np.empty(((n << level) + 1, (n << level) + 1), np.float32)
    for tx, ty, zf in dem.tiles(level):
        grid[ty * n:ty * n + n + 1, tx * n:tx * n + n + 1] = zf[2:-2, 2:-2]
    return grid[::-1]


def fail(message):
    print(f"python_pipeline: {message}", file=sys.stderr)
    sys.exit(1)


def main():
    if len(sys.argv) not in (2, 3):
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    dem_path = out / "DEM.dat"
    if len(sys.argv) == 3:
        report = libpyramid.encode_dem(sys.argv[2], dem_path, scale=0.5)
    else:
        heights = volcano()
        report = libpyramid.encode_dem(heights, dem_path, scale=0.5, tile_size="auto")
    scale = report["header"]["scale"]
    with libpyramid.open(dem_path) as dem:
        if len(sys.argv) == 3:
            heights = finest_grid(dem)
            g = dem.info["georeference"]
            if g is not None and g["crs"]["kind"] == "geographic":
                e = g["root_extent"]
                lon, lat = (e["min_x"] + e["max_x"]) / 2, (e["min_y"] + e["max_y"]) / 2
                h = dem.height(lon=lon, lat=lat)
                where = f"({lon:.4f}, {lat:.4f})"
            else:
                h = dem.height(u=0.5, v=0.5)
                where = "the centre"
            # The root quad's centre is a sample of the finest level: the height is that sample.
            centre = float(heights[heights.shape[0] // 2, heights.shape[1] // 2])
            if abs(h - centre) > 1e-3:
                fail(f"{dem_path}: the height at {where} is {h}, its finest sample {centre}")
            check = f"height at {where}: {h:.1f}"
        else:
            error = float(np.abs(finest_grid(dem).astype(np.float64) - heights).max())
            if error > scale / 2 + 1e-3:
                fail(f"{dem_path}: a finest sample is {error} from the array, more than scale / 2 = {scale / 2}")
            check = f"every finest sample within {error:.3f} of the array (scale / 2 = {scale / 2})"
            h = dem.height(u=0.55, v=1 - 0.45)
            check += f"; summit {h:.1f}"
        levels = len(dem.levels)
    ortho = libpyramid.encode_ortho(shade(heights), out / "ortho", outputs=["tiff"])
    with libpyramid.open(out / "ortho" / "RGB.dat") as o:
        tiles = sum(1 for level in o.levels for _ in o.tiles(level))
    print(f"DEM: {dem_path} ({report['bytes']} bytes, {report['tiles']} tiles, {levels} levels, scale {scale})")
    print(f"check: {check}")
    print(f"ortho: {ortho['outputs']['tiff']} ({tiles} tiles of {o.side} pixels)")
    print("pipeline ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
