"""Threads: the GIL is released during C calls, so threads share handles and read in parallel."""

import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

import libpyramid
from conftest import DEM, RGB, smooth_heights

WORK = [("e", level, tx, ty) for level in range(4) for tx in range(1 << level) for ty in range(1 << level)]
WORK += [("n", level, tx, ty) for level in range(2) for tx in range(1 << level) for ty in range(1 << level)]
WORK += [("o", level, tx, ty) for level in range(2) for tx in range(1 << level) for ty in range(1 << level)]


def run_item(dem, rgb, item):
    kind, level, tx, ty = item
    if kind == "e":
        return dem.elevation(level, tx, ty, coarse=True)[1]
    if kind == "n":
        return dem.normals(level, tx, ty, size=24000)
    return rgb.tile(level, tx, ty)


def test_threads_sharing_handles_get_the_serial_results():
    # A cache of one tile: the threads keep evicting each other's tiles and rebuilding parents.
    with libpyramid.open(DEM, cache_tiles=1) as dem, libpyramid.open(RGB, cache_tiles=1) as rgb:
        serial = [run_item(dem, rgb, w) for w in WORK]
    with libpyramid.open(DEM, cache_tiles=1) as dem, libpyramid.open(RGB, cache_tiles=1) as rgb:
        with ThreadPoolExecutor(8) as pool:
            for rounds in range(3):
                order = list(range(len(WORK)))[rounds::3] + list(range(len(WORK)))
                results = list(pool.map(lambda i: (i, run_item(dem, rgb, WORK[i])), order))
                for i, array in results:
                    assert np.array_equal(array, serial[i]), WORK[i]


def test_the_gil_is_free_during_an_encoding(tmp_path):
    """While an encoding runs in another thread, this thread keeps running Python."""
    heights = smooth_heights(1537, 1537)
    ticks = 0
    worker = threading.Thread(target=libpyramid.encode_dem, args=(heights, tmp_path / "DEM.dat"),
                              kwargs={"threads": 1})
    worker.start()
    started = time.monotonic()
    while worker.is_alive():
        ticks += 1
    elapsed = time.monotonic() - started
    worker.join()
    assert (tmp_path / "DEM.dat").exists()
    # Held by the C call, the GIL would stop this loop for the whole encoding; free, it runs
    # millions of times a second (100 000 leaves room for a loaded machine).
    assert elapsed > 0.05 and ticks > 100_000 * elapsed, (ticks, elapsed)
