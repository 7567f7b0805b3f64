#!/usr/bin/env python3
"""How small the residual tiles of a DEM file can get as TIFFs: a bound for `--compression smallest`.

    PYRAMID_LIBRARY=build-release/libpyramid python3 bench/residual_layouts.py DEM.dat [--gdal COG.tif] [--zopfli]

A benchmark, run on demand (never a test). It reads every distinct residual tile of DEM.dat
through the Python package (the C API) and compresses its strip bytes in each layout a TIFF tile
can take, each with libdeflate at level 12 (the level `smallest` uses):

* `2x8`: 2 samples of 8 bits, the low byte then the high byte (the original tools' layout);
* `2x8+p2`: the same with Predictor 2 (each byte minus the same byte of the pixel to its left);
* `1x16+p2`: 1 signed sample of 16 bits with Predictor 2 (differences modulo 2^16, low byte first);
* `fp16+p3`: 1 sample of 16 bits declared IEEE float with Predictor 3, which libtiff undoes into
  the same strip bytes (each row's high bytes, then its low bytes, differenced byte by byte);

then `best of 3` (per tile the smallest of the first three: what `--compression smallest`
writes) and `best of 4`. Two bounds beyond libdeflate's parsing: `--zopfli` recompresses each
tile's best-of-3 layout with zopfli (15 iterations; `apt-get install zopfli`, slow), and `lzma`
compresses each tile's best layout with LZMA1 (preset 9e, lc 0, lp 1, pb 1): a codec libtiff
decodes (Compression 34925) but that the original runtime's libtiff need not have, reported as a
bound, not as an option. `file bytes` is the file's size with its tiles' compressed strips
replaced by each variant's (their TIFF headers kept as they are); with `--gdal`, that over the
COG's size. A file written by `--compression smallest` gives its own size on `best of 3`.
"""
import argparse
import ctypes
import ctypes.util
import lzma
import os
import struct
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import libpyramid  # noqa: E402


def libdeflate12():
    lib = ctypes.CDLL(ctypes.util.find_library("deflate") or "libdeflate.so.0")
    lib.libdeflate_alloc_compressor.restype = ctypes.c_void_p
    lib.libdeflate_zlib_compress.restype = ctypes.c_size_t
    lib.libdeflate_zlib_compress.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_size_t,
                                             ctypes.c_void_p, ctypes.c_size_t]
    compressor = lib.libdeflate_alloc_compressor(12)
    out = ctypes.create_string_buffer(1 << 22)

    def size(data):
        return lib.libdeflate_zlib_compress(compressor, data, len(data), out, len(out))
    return size


def layouts(r):
    """The strip bytes of residual tile `r` (int16, row 0 = strip row 0) in each layout."""
    v = r.astype(np.int32)
    low, high = v & 0xFF, (v >> 8) & 0xFF
    pairs = np.stack([low, high], axis=2)
    pairs_p2 = pairs.copy()
    pairs_p2[:, 1:, :] = pairs[:, 1:, :] - pairs[:, :-1, :]
    words_p2 = v.copy()
    words_p2[:, 1:] = v[:, 1:] - v[:, :-1]
    planes = np.concatenate([high, low], axis=1)
    planes_p3 = planes.copy()
    planes_p3[:, 1:] = planes[:, 1:] - planes[:, :-1]
    return {
        "2x8": (pairs & 0xFF).astype(np.uint8).tobytes(),
        "2x8+p2": (pairs_p2 & 0xFF).astype(np.uint8).tobytes(),
        "1x16+p2": (words_p2 & 0xFFFF).astype("<u2").tobytes(),
        "fp16+p3": (planes_p3 & 0xFF).astype(np.uint8).tobytes(),
    }


def strip_bytes(blob, where):
    """The compressed bytes of a TIFF tile's strips (StripByteCounts), from its first IFD."""
    if blob[:4] == b"PYRC":
        sys.exit(f"{where}: a context-coded tile; this measures files of TIFF tiles")
    order = {b"II": "<", b"MM": ">"}.get(blob[:2])
    if order is None or struct.unpack(order + "H", blob[2:4])[0] != 42:
        sys.exit(f"{where}: not a classic TIFF tile")
    ifd = struct.unpack(order + "I", blob[4:8])[0]
    (entries,) = struct.unpack(order + "H", blob[ifd:ifd + 2])
    for k in range(entries):
        tag, kind, count, value = struct.unpack(order + "HHII", blob[ifd + 2 + 12 * k:ifd + 14 + 12 * k])
        if tag == 279:
            size = {3: 2, 4: 4}[kind]
            if count * size <= 4:
                return sum(struct.unpack(order + ("H" if size == 2 else "I") * count,
                                         blob[ifd + 10 + 12 * k:ifd + 10 + 12 * k + count * size]))
            return sum(struct.unpack(order + ("H" if size == 2 else "I") * count, blob[value:value + count * size]))
    sys.exit(f"{where}: a TIFF tile without StripByteCounts")


def distinct_tiles(dem):
    """(residuals, compressed strip bytes) of every distinct stored tile (shared tiles once)."""
    info = dem.info
    seen = set()
    for level in range(info["max_level"] + 1):
        side = 1 << max(0, level - info["min_level"])
        for ty in range(side):
            for tx in range(side):
                offset = dem.tile_info(level, tx, ty)["offset"]
                if offset not in seen:
                    seen.add(offset)
                    blob = dem.tile_bytes(level, tx, ty)
                    yield dem.residual(level, tx, ty), strip_bytes(blob, f"tile ({level}, {tx}, {ty})")


def zopfli_size(data, scratch):
    with open(scratch, "wb") as f:
        f.write(data)
    subprocess.run(["zopfli", "--zlib", "--i15", scratch], check=True)
    return os.path.getsize(scratch + ".zlib")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dem")
    parser.add_argument("--gdal", help="a COG of the same DEM, for the ratios")
    parser.add_argument("--zopfli", action="store_true")
    args = parser.parse_args()
    deflated = libdeflate12()
    lzma_filters = [{"id": lzma.FILTER_LZMA1, "preset": 9 | lzma.PRESET_EXTREME, "lc": 0, "lp": 1, "pb": 1}]
    totals = {}
    tiles = 0
    stored = 0
    with libpyramid.open(args.dem) as dem, tempfile.TemporaryDirectory() as scratch:
        for r, strips_stored in distinct_tiles(dem):
            tiles += 1
            stored += strips_stored
            strips = layouts(r)
            sizes = {name: deflated(data) for name, data in strips.items()}
            best3 = min(("2x8", "2x8+p2", "1x16+p2"), key=lambda name: sizes[name])
            sizes["best of 3"] = sizes[best3]
            sizes["best of 4"] = min(sizes.values())
            if args.zopfli:
                sizes["zopfli, best of 3's layout"] = zopfli_size(strips[best3], os.path.join(scratch, "tile"))
            sizes["lzma, best layout"] = min(len(lzma.compress(data, format=lzma.FORMAT_RAW, filters=lzma_filters))
                                             for data in strips.values())
            for name, size in sizes.items():
                totals[name] = totals.get(name, 0) + size
    file_bytes = os.path.getsize(args.dem)
    gdal_bytes = os.path.getsize(args.gdal) if args.gdal else None
    print(f"{args.dem}: {tiles} distinct tiles, {file_bytes} bytes, {stored} of them compressed strips")
    print(f"{'tiles as':<28} {'payload':>10} {'/ best of 3':>12} {'file bytes':>11}" + ("  / GDAL" if gdal_bytes else ""))
    for name, total in totals.items():
        whole = file_bytes - stored + total
        line = f"{name:<28} {total:>10} {total / totals['best of 3']:>12.3f} {whole:>11}"
        if gdal_bytes:
            line += f"  {whole / gdal_bytes:.3f}"
        print(line)


if __name__ == "__main__":
    main()
