#!/usr/bin/env python3
"""Measures what ctypes adds to a call against what the C API's work costs (doc/python.md).

    python3 measure_overhead.py DEM.dat RGB.dat

Prints microseconds per call of: an empty foreign call; the package's elevation() on a cached
tile (the C side only copies 197^2 floats) and the bare ctypes call under it; a produced
elevation tile (decode + upsample, parents cached, as a renderer walks the quadtree); a decoded
ortho tile; an encoding per tile, through the package and as a bare C call. Run it with the
installed package on the path.
"""

import ctypes
import sys
import time

import numpy as np

import libpyramid
from libpyramid import _capi


def per_call(fn, seconds=0.5):
    """Microseconds per call of fn(), the best of three runs of about `seconds` / 3 each."""
    n, start = 0, time.perf_counter()
    while time.perf_counter() - start < 0.05:
        fn()
        n += 1
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        for _ in range(n * max(1, int(seconds / 0.15))):
            fn()
        best = min(best, (time.perf_counter() - start) / (n * max(1, int(seconds / 0.15))))
    return best * 1e6


def fastest(fn, runs=10):
    """Microseconds of the fastest of `runs` calls of fn() (long calls on a busy machine)."""
    best = float("inf")
    for _ in range(runs):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best * 1e6


def encode_rows(side=1025):
    """An encoding through the package (worker thread, cancel callback after every tile) against
    the bare C call (no callbacks), per tile."""
    import os
    import tempfile
    y, x = np.mgrid[0:side, 0:side].astype(np.float32)
    heights = (500 + 200 * np.sin(x / 40) * np.cos(y / 30)).astype(np.float32)
    lib = _capi.encode_library()
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "DEM.dat")
        tiles = libpyramid.encode_dem(heights, out, threads=1)["tiles"]
        src = _capi.sized(_capi.pyramid_height_source)
        src.width = src.height = side
        src.heights = heights.ctypes.data_as(_capi.c_float_p)
        o = _capi.sized(_capi.pyramid_dem_encode_options)
        lib.pyramid_dem_encode_defaults(ctypes.byref(o))
        o.threads = 1
        bare = fastest(lambda: lib.pyramid_encode_dem(ctypes.byref(src), ctypes.byref(o), out.encode()))
        package = fastest(lambda: libpyramid.encode_dem(heights, out, threads=1))
    return [(f"encode_dem {side}^2, 1 thread, per tile ({tiles} tiles): bare C call", bare / tiles),
            (f"encode_dem {side}^2, 1 thread, per tile ({tiles} tiles): the package", package / tiles)]


def main():
    dem_path, rgb_path = sys.argv[1:3]
    lib = _capi.runtime
    rows = [("empty foreign call (pyramid_version_number)", per_call(lib.pyramid_version_number))]
    with libpyramid.open(dem_path, cache_tiles=256) as dem:
        dem.elevation(1, 1, 0)
        rows.append(("dem.elevation(), cached tile (numpy array made)", per_call(lambda: dem.elevation(1, 1, 0))))
        zf = np.empty((dem.side, dem.side), np.float32)
        address, count = zf.ctypes.data, zf.size
        rows.append(("bare pyramid_elevation_tile, cached tile, same buffer",
                     per_call(lambda: lib.pyramid_elevation_tile(dem._elevation, 1, 1, 0, address, None, None, count))))
    tiles = [(level, tx, ty) for level in range(4) for ty in range(1 << level) for tx in range(1 << level)]

    def walk():
        with libpyramid.open(dem_path, cache_tiles=256) as fresh:
            for t in tiles:
                fresh.elevation(*t)

    rows.append((f"produced elevation tile (walk of {len(tiles)} tiles, levels 0..3)", per_call(walk, 2) / len(tiles)))
    with libpyramid.open(rgb_path) as rgb:
        rows.append(("ortho.tile(), decoded TIFF tile 196^2 x 4", per_call(lambda: rgb.tile(1, 1, 1))))
    rows += encode_rows()
    width = max(len(r[0]) for r in rows)
    for name, us in rows:
        print(f"{name:<{width}}  {us:10.2f} us")
    print(f"ctypes {ctypes.__name__} on Python {sys.version.split()[0]}, libpyramid {libpyramid.version()}")


if __name__ == "__main__":
    main()
