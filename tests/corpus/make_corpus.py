#!/usr/bin/env python3
"""Writes the corpus of broken pyramid files, TIFF tiles and DXT blobs (tests/corpus).

Every file breaks exactly one rule of doc/format.md; the valid files it is derived from are
written to valid/ so that the test can prove the breakage is the only problem. MANIFEST lists
every file, how the test decodes it and a fragment of the expected error message.

Deterministic (python3 standard library only): running it again rewrites the same bytes.
Usage: python3 tests/corpus/make_corpus.py
"""
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
PROLAND = os.path.join(HERE, "..", "data", "proland")

manifest = []  # (relative path, decoder, expected error fragment or "ok")


def emit(relative, data, decoder, expected):
    path = os.path.join(HERE, relative)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)
    manifest.append((relative, decoder, expected))


# ------------------------------------------------------------------ TIFF writing (little endian)

SHORT, LONG = 3, 4


def tiff(width, height, spp=1, bps=8, strips=None, compression=1, photometric=None, sample_format=1,
         planar=1, rows_per_strip=None, byte_counts=None, extra=None):
    """A strip TIFF; `strips` are the stored (already compressed) strip bytes."""
    if photometric is None:
        photometric = 2 if spp >= 3 else 1
    body = bytearray(b"II*\0\0\0\0\0")
    offsets = []
    for strip in strips:
        offsets.append(len(body))
        body += strip
        if len(body) % 2:
            body += b"\0"
    tags = {
        256: (LONG, [width]),
        257: (LONG, [height]),
        258: (SHORT, [bps] * spp),
        259: (SHORT, [compression]),
        262: (SHORT, [photometric]),
        273: (LONG, offsets),
        277: (SHORT, [spp]),
        278: (LONG, [rows_per_strip if rows_per_strip is not None else height]),
        279: (LONG, byte_counts if byte_counts is not None else [len(s) for s in strips]),
        284: (SHORT, [planar]),
        339: (SHORT, [sample_format] * spp),
    }
    tags.update(extra or {})
    entries = []
    for tag in sorted(tags):
        kind, values = tags[tag]
        fmt = "<%d%s" % (len(values), "H" if kind == SHORT else "I")
        packed = struct.pack(fmt, *values)
        if len(packed) <= 4:
            entries.append(struct.pack("<HHI", tag, kind, len(values)) + packed.ljust(4, b"\0"))
        else:
            entries.append(struct.pack("<HHII", tag, kind, len(values), len(body)))
            body += packed
            if len(body) % 2:
                body += b"\0"
    ifd = len(body)
    body += struct.pack("<H", len(entries)) + b"".join(entries) + struct.pack("<I", 0)
    body[4:8] = struct.pack("<I", ifd)
    return bytes(body)


def strip_past_end(width, height, spp):
    """An uncompressed TIFF whose only strip starts 8 bytes before the end of the file."""
    full = width * height * spp
    probe = tiff(width, height, spp=spp, strips=[b""], byte_counts=[full])
    return tiff(width, height, spp=spp, strips=[b""], byte_counts=[full], extra={273: (LONG, [len(probe) - 8])})


def deflate(raw):
    return zlib.compress(raw, 6)


def residual_tiff(size, seed=0):
    """A valid residual tile: size x size int16 as 2 x 8-bit samples, Deflate."""
    values = [((k * 37 + seed * 101) % 2001) - 1000 for k in range(size * size)]
    raw = b"".join(struct.pack("<h", v) for v in values)
    return tiff(size, size, spp=2, strips=[deflate(raw)], compression=8)


def gradient(width, height, channels):
    return bytes((3 * x + 2 * y + 40 * c) % 256 for y in range(height) for x in range(width) for c in range(channels))


def ortho_tiff(size, channels):
    return tiff(size, size, spp=channels, strips=[deflate(gradient(size, size, channels))], compression=8)


# ------------------------------------------------------------------ pyramid files


def residual_header(min_level, max_level, tile_size, root=(0, 0, 0), scale=1.0):
    return struct.pack("<6if", min_level, max_level, tile_size, root[0], root[1], root[2], scale)


def ortho_header(max_level, tile_size, channels, flags, root=(0, 0, 0)):
    return struct.pack("<6iI", max_level, tile_size, channels, root[0], root[1], root[2], flags)


def pyramid(header, blobs, offset_format):
    """Header, offset table (`offset_format` "I" or "q"), then the blobs back to back."""
    table, data = [], b""
    for blob in blobs:
        table += [len(data), len(data) + len(blob)]
        data += blob
    return header + struct.pack("<%d%s" % (len(table), offset_format), *table) + data


def with_table(header, pairs, data, offset_format):
    flat = [v for pair in pairs for v in pair]
    return header + struct.pack("<%d%s" % (len(flat), offset_format), *flat) + data


def read(name):
    with open(os.path.join(PROLAND, name), "rb") as f:
        return f.read()


def residual_tiles(data):
    """The tile blobs of a residual file, in table order."""
    min_level, max_level = struct.unpack("<2i", data[:8])
    count = min_level + ((1 << (2 * (max_level - min_level + 1))) - 1) // 3
    table = struct.unpack("<%dI" % (2 * count), data[28:28 + 8 * count])
    start = 28 + 8 * count
    return [data[start + table[2 * i]:start + table[2 * i + 1]] for i in range(count)]


def ortho_tiles(data):
    max_level = struct.unpack("<i", data[:4])[0]
    count = ((1 << (2 * (max_level + 1))) - 1) // 3
    table = struct.unpack("<%dq" % (2 * count), data[28:28 + 16 * count])
    start = 28 + 16 * count
    return [data[start + table[2 * i]:start + table[2 * i + 1]] for i in range(count)]


def main():
    dem = read("DEM.dat")
    rgb = read("RGB.dat")
    dem_tiles = residual_tiles(dem)  # levels 0..2 hold 29, 53 and 101 samples a side
    rgb_tiles = ortho_tiles(rgb)     # 196 x 196 x 4 with borders

    # ---- valid files every broken one derives from (levels 0..2 of DEM.dat re-headed as
    # minLevel 2, tileSize 96: the same 29, 53, 101 samples; level 0 of RGB.dat).
    dem3 = [dem_tiles[0], dem_tiles[1], dem_tiles[2]]
    dem_small_header = residual_header(2, 2, 96, scale=0.1)
    emit("valid/dem-levels-0-2.dat", pyramid(dem_small_header, dem3, "I"), "residual", "ok")
    rgb_small_header = ortho_header(0, 192, 4, 0)
    emit("valid/rgb-level-0.dat", pyramid(rgb_small_header, [rgb_tiles[0]], "q"), "ortho", "ok")
    tiny_res_header = residual_header(0, 0, 4)  # one 9 x 9 tile
    emit("valid/tiny-residual.dat", pyramid(tiny_res_header, [residual_tiff(9)], "I"), "residual", "ok")
    tiny_ortho_header = ortho_header(0, 4, 3, 2)  # one 4 x 4 x 3 tile, no border
    emit("valid/tiny-ortho.dat", pyramid(tiny_ortho_header, [ortho_tiff(4, 3)], "q"), "ortho", "ok")
    dxt1_header = ortho_header(0, 4, 3, 3)
    dxt5_header = ortho_header(0, 4, 4, 3)
    dxt1_block = bytes([0x00, 0xf8, 0x1f, 0x00, 0x1b, 0x6c, 0xb1, 0xe4])
    dxt5_block = bytes([0xff, 0x10, 0x49, 0x92, 0x24, 0x49, 0x92, 0x24]) + dxt1_block
    emit("valid/tiny-dxt1.dat", pyramid(dxt1_header, [dxt1_block], "q"), "ortho", "ok")
    emit("valid/tiny-dxt5.dat", pyramid(dxt5_header, [dxt5_block], "q"), "ortho", "ok")
    emit("valid/tiny.tif", ortho_tiff(4, 3), "ortho-tiff 4 3", "ok")
    emit("valid/residual-9.tif", residual_tiff(9), "residual-tiff 9", "ok")
    emit("valid/dxt1-4x4.bin", dxt1_block, "dxt1 4 4", "ok")

    # ---- residual files
    R = "residual"
    emit("residual/empty.dat", b"", R, "empty file")
    emit("residual/dem-truncated-header.dat", dem[:20], R, "shorter than a pyramid header")
    emit("residual/dem-truncated-table.dat", dem[:28 + 100], R, "offset table of 24 tiles")
    emit("residual/dem-offsets-past-end.dat", dem[:28 + 192 + 17686], R, "past the end of the tile data")
    small_pairs = [(0, 1066), (1066, 4786), (4786, 17686)]
    small_data = b"".join(dem3)
    emit("residual/dem-reversed-offsets.dat",
         with_table(dem_small_header, [(0, 1066), (4786, 1066), (4786, 17686)], small_data, "I"), R, "reversed")
    emit("residual/dem-huge-offset.dat",
         with_table(dem_small_header, [(0, 1066), (1066, 0xffffffff), (4786, 17686)], small_data, "I"), R,
         "past the end")
    emit("residual/dem-missing-tile.dat",
         with_table(dem_small_header, [(0, 1066), (1066, 1066), (4786, 17686)], small_data, "I"), R, "is missing")
    # The original tools write the TIFF directory after the strip: a cut tile loses it.
    emit("residual/dem-truncated-tile.dat",
         with_table(dem_small_header, [(0, 1066), (1066, 4786), (4786, 9000)], small_data, "I"), R,
         "not a readable TIFF")
    emit("residual/dem-shifted-tile.dat",
         with_table(dem_small_header, [(0, 1066), (1067, 4786), (4786, 17686)], small_data, "I"), R,
         "not a readable TIFF")
    emit("residual/dem-tiles-swapped.dat",
         with_table(dem_small_header, [(1066, 4786), (0, 1066), (4786, 17686)], small_data, "I"), R,
         "TIFF of 53x53 pixels, expected at most 29x29")
    emit("residual/dem-tile-size-doubled.dat", pyramid(residual_header(2, 2, 192, scale=0.1), dem3, "I"), R,
         "residual tile of 29x29 samples, expected 53x53")

    def dem_header(**fields):
        values = dict(min_level=2, max_level=2, tile_size=96, root=(0, 0, 0), scale=0.1)
        values.update(fields)
        return pyramid(residual_header(**values), dem3, "I")

    emit("residual/max-level-31.dat", dem_header(max_level=31), R, "invalid levels")
    emit("residual/min-level-above-max.dat", dem_header(min_level=3), R, "invalid levels")
    emit("residual/negative-min-level.dat", dem_header(min_level=-1), R, "invalid levels")
    emit("residual/max-level-30.dat", dem_header(min_level=0, max_level=30, tile_size=96), R, "too short")
    emit("residual/tile-size-0.dat", dem_header(tile_size=0), R, "invalid tileSize 0")
    emit("residual/tile-size-2-pow-20.dat", dem_header(tile_size=1 << 20), R, "invalid tileSize 1048576")
    emit("residual/tile-size-not-divisible.dat", dem_header(tile_size=98), R, "not divisible")
    emit("residual/root-outside-level.dat", dem_header(min_level=0, max_level=0, root=(1, 2, 0)), R,
         "invalid root tile")
    emit("residual/region-with-min-level.dat", dem_header(root=(3, 1, 1)), R, "must have minLevel 0")
    emit("residual/scale-zero.dat", dem_header(scale=0.0), R, "invalid scale")
    emit("residual/scale-nan.dat", dem_header(scale=float("nan")), R, "invalid scale")
    emit("residual/scale-negative.dat", dem_header(scale=-1.0), R, "invalid scale")
    emit("residual/orthofile.dat", pyramid(tiny_ortho_header, [ortho_tiff(4, 3)], "q"), R, "too short")

    def tiny_residual(blob):
        return pyramid(tiny_res_header, [blob], "I")

    emit("residual/tile-not-tiff.dat", tiny_residual(b"this is not a TIFF tile at all"), R, "not a readable TIFF")
    emit("residual/tile-tiff-too-big.dat", tiny_residual(residual_tiff(10)), R, "TIFF of 10x10 pixels")
    emit("residual/tile-tiff-too-small.dat", tiny_residual(residual_tiff(8)), R, "residual tile of 8x8 samples")
    emit("residual/tile-float-samples.dat",
         tiny_residual(tiff(9, 9, bps=16, strips=[bytes(162)], sample_format=3)), R, "floating-point")
    emit("residual/tile-3-samples.dat", tiny_residual(ortho_tiff(9, 3)), R, "3 x 8-bit samples")
    emit("residual/tile-1x8-bit.dat", tiny_residual(ortho_tiff(9, 1)), R, "1 x 8-bit samples")
    # 8197 x 8197 x 4 x 16 bits (537 MB) declared in a few hundred bytes: rejected before allocation.
    emit("residual/tile-huge-wrong-layout.dat",
         pyramid(residual_header(0, 0, 8192), [tiff(8197, 8197, spp=4, bps=16, strips=[deflate(bytes(64))],
                                                    compression=8)], "I"), R, "4 x 16-bit samples")
    # The right layout for tileSize 8192 (8197 x 8197 x 2 x 8 bits, 134 MB) in a few dozen
    # stored bytes, which no codec expands that far: rejected before allocation.
    emit("residual/tile-huge-few-bytes.dat",
         pyramid(residual_header(0, 0, 8192), [tiff(8197, 8197, spp=2, strips=[deflate(bytes(64))],
                                                    compression=8)], "I"), R, "stored bytes cannot hold")
    emit("residual/tile-huge-uncompressed-few-bytes.dat",
         pyramid(residual_header(0, 0, 8192), [tiff(8197, 8197, spp=2, strips=[bytes(4096)])], "I"), R,
         "stored bytes cannot hold")
    truncated = residual_tiff(9)
    emit("residual/tile-strip-past-end.dat",
         tiny_residual(strip_past_end(9, 9, 2)), R, "truncated or corrupt")
    emit("residual/tile-truncated-deflate.dat",
         tiny_residual(tiff(9, 9, spp=2, strips=[deflate(bytes(162))[:6]], compression=8)), R,
         "truncated or corrupt")
    emit("residual/tile-cut.dat", tiny_residual(truncated[:len(truncated) // 2]), R, "not a readable TIFF")

    # ---- ortho files
    O = "ortho"
    rgb_small = pyramid(rgb_small_header, [rgb_tiles[0]], "q")
    emit("ortho/empty.dat", b"", O, "empty file")
    emit("ortho/rgb-truncated-header.dat", rgb[:27], O, "shorter than a pyramid header")
    emit("ortho/rgb-truncated-table.dat", rgb[:28 + 40], O, "offset table of 5 tiles")
    emit("ortho/rgb-offsets-past-end.dat", rgb[:28 + 80 + 38188], O, "past the end of the tile data")
    emit("ortho/rgb-reversed-offsets.dat", with_table(rgb_small_header, [(38188, 0)], rgb_tiles[0], "q"), O,
         "reversed")
    emit("ortho/rgb-negative-offset.dat", with_table(rgb_small_header, [(-16, 38188)], rgb_tiles[0], "q"), O,
         "negative offset")
    emit("ortho/rgb-most-negative-offset.dat",
         with_table(rgb_small_header, [(0, -(1 << 63))], rgb_tiles[0], "q"), O, "negative offset")
    emit("ortho/rgb-missing-tile.dat", with_table(rgb_small_header, [(5, 5)], rgb_tiles[0], "q"), O, "is missing")
    emit("ortho/rgb-truncated-tile.dat", with_table(rgb_small_header, [(0, 20000)], rgb_tiles[0], "q"), O,
         "not a readable TIFF")

    def rgb_header(max_level=0, tile_size=192, channels=4, flags=0, root=(0, 0, 0)):
        return ortho_header(max_level, tile_size, channels, flags, root) + rgb_small[28:]

    # Headers rejected before any tile is looked at keep the small table and tile of tiny-ortho.
    tiny_ortho_tail = pyramid(tiny_ortho_header, [ortho_tiff(4, 3)], "q")[28:]

    def bad_header(max_level=0, tile_size=4, channels=3, flags=2, root=(0, 0, 0)):
        return ortho_header(max_level, tile_size, channels, flags, root) + tiny_ortho_tail

    emit("ortho/max-level-31.dat", bad_header(max_level=31), O, "invalid maxLevel 31")
    emit("ortho/max-level-negative.dat", bad_header(max_level=-1), O, "invalid maxLevel -1")
    emit("ortho/max-level-30.dat", bad_header(max_level=30), O, "too short")
    emit("ortho/tile-size-0.dat", bad_header(tile_size=0), O, "invalid tileSize 0")
    emit("ortho/tile-size-2-pow-20.dat", bad_header(tile_size=1 << 20), O, "invalid tileSize 1048576")
    emit("ortho/channels-0.dat", bad_header(channels=0), O, "invalid channel count 0")
    emit("ortho/channels-5.dat", bad_header(channels=5), O, "invalid channel count 5")
    emit("ortho/channels-3-for-rgba-tile.dat", rgb_header(channels=3), O, "4 x 8-bit samples, expected 3 x 8")
    emit("ortho/no-border-flag-on-bordered-tile.dat", rgb_header(flags=2), O, "TIFF of 196x196 pixels")
    emit("ortho/unknown-flags.dat", bad_header(flags=6), O, "unknown flags 6")
    emit("ortho/high-flag-bit.dat", bad_header(flags=0x80000002), O, "unknown flags")
    emit("ortho/dxt-flag-on-tiff-tiles.dat", rgb_header(flags=1), O, "DXT tile of 38188 bytes")
    emit("ortho/root-outside-level.dat", bad_header(root=(2, 0, 4)), O, "invalid root tile")
    emit("ortho/root-level-31.dat", bad_header(root=(31, 0, 0)), O, "invalid root tile")
    emit("ortho/residualfile.dat", pyramid(tiny_res_header, [residual_tiff(9)], "I"), O, "invalid tileSize 0")

    def tiny_ortho(blob, header=tiny_ortho_header):
        return pyramid(header, [blob], "q")

    emit("ortho/tile-not-tiff.dat", tiny_ortho(b"\x89PNG\r\n\x1a\n not a TIFF either"), O, "not a readable TIFF")
    emit("ortho/tile-tiff-too-big.dat", tiny_ortho(ortho_tiff(5, 3)), O, "TIFF of 5x5 pixels")
    emit("ortho/tile-tiff-too-small.dat", tiny_ortho(ortho_tiff(3, 3)), O, "ortho tile of 3x3 pixels")
    emit("ortho/tile-float-samples.dat", tiny_ortho(tiff(4, 4, spp=3, bps=32, strips=[bytes(192)], sample_format=3)),
         O, "32 bits per sample")
    emit("ortho/tile-16-bit.dat", tiny_ortho(tiff(4, 4, spp=3, bps=16, strips=[bytes(96)])), O,
         "3 x 16-bit samples, expected 3 x 8")
    emit("ortho/tile-huge-wrong-layout.dat",
         tiny_ortho(tiff(8196, 8196, spp=4, bps=16, strips=[deflate(bytes(64))], compression=8),
                    ortho_header(0, 8192, 3, 0)), O, "4 x 16-bit samples, expected 3 x 8")
    emit("ortho/tile-1-channel.dat", tiny_ortho(ortho_tiff(4, 1)), O, "1 x 8-bit samples, expected 3 x 8")
    emit("ortho/tile-strip-past-end.dat", tiny_ortho(strip_past_end(4, 4, 3)), O,
         "truncated or corrupt")
    emit("ortho/dxt1-short-blob.dat", tiny_ortho(dxt1_block[:7], dxt1_header), O, "DXT tile of 7 bytes, expected 8")
    emit("ortho/dxt1-long-blob.dat", tiny_ortho(dxt1_block + b"\0", dxt1_header), O, "DXT tile of 9 bytes")
    emit("ortho/dxt5-with-dxt1-blob.dat", tiny_ortho(dxt1_block, dxt5_header), O, "DXT tile of 8 bytes, expected 16")
    emit("ortho/dxt-1-channel.dat", tiny_ortho(dxt1_block, ortho_header(0, 4, 1, 3)), O, "DXT file with 1 channels")
    emit("ortho/dxt-tile-not-multiple-of-4.dat", tiny_ortho(dxt1_block, ortho_header(0, 5, 3, 3)), O,
         "a multiple of 4 expected")

    # ---- TIFF tiles on their own (decoded as 9 x 9 residual or 4 x 4 x 3 ortho tiles)
    RT, OT = "residual-tiff 9", "ortho-tiff 4 3"
    emit("tiff/empty.tif", b"", RT, "not a TIFF (0 bytes)")
    emit("tiff/header-only.tif", b"II*\0\x08\0\0\0", RT, "not a readable TIFF")
    emit("tiff/big-endian-garbage.tif", b"MM\0*\xff\xff\xff\xff" + bytes(32), RT, "not a readable TIFF")
    emit("tiff/not-tiff.tif", b"GIF89a" + bytes(40), OT, "not a readable TIFF")
    emit("tiff/ifd-loop.tif", b"II*\0\x08\0\0\0" + struct.pack("<H", 0) + struct.pack("<I", 8), RT,
         "not a readable TIFF")
    emit("tiff/huge-dimensions.tif", tiff(1 << 30, 1 << 30, spp=2, strips=[bytes(64)]), RT,
         "TIFF of 1073741824x1073741824 pixels, expected at most 9x9")
    emit("tiff/zero-width.tif", tiff(0, 9, spp=2, strips=[bytes(8)]), RT, "not a readable TIFF")
    emit("tiff/wrong-size.tif", residual_tiff(7), RT, "residual tile of 7x7 samples, expected 9x9")
    emit("tiff/float32-samples.tif", tiff(9, 9, bps=32, strips=[bytes(324)], sample_format=3), RT,
         "32 bits per sample")
    emit("tiff/float16-samples.tif", tiff(9, 9, bps=16, strips=[bytes(162)], sample_format=3), RT, "floating-point")
    emit("tiff/complex-samples.tif", tiff(9, 9, bps=16, strips=[bytes(162)], sample_format=5), RT,
         "floating-point or complex")
    emit("tiff/1-bit.tif", tiff(9, 9, bps=1, strips=[bytes(18)]), RT, "1 bits per sample")
    emit("tiff/3-samples-as-residual.tif", ortho_tiff(9, 3), RT, "3 x 8-bit samples")
    emit("tiff/4-samples-16-bit-as-residual.tif", tiff(9, 9, spp=4, bps=16, strips=[bytes(648)]), RT,
         "4 x 16-bit samples")
    emit("tiff/5-samples.tif", tiff(4, 4, spp=5, strips=[bytes(80)]), OT, "5 samples per pixel")
    emit("tiff/separate-planes.tif",
         tiff(4, 4, spp=3, strips=[bytes(16)] * 3, planar=2, rows_per_strip=4), OT, "separate colour planes")
    emit("tiff/strip-count-mismatch.tif", tiff(4, 4, spp=3, strips=[bytes(48)], rows_per_strip=1), OT,
         "strip 1 has no data")
    emit("tiff/strip-past-end.tif", strip_past_end(4, 4, 3), OT,
         "truncated or corrupt")
    emit("tiff/strip-offset-past-end.tif",
         tiff(4, 4, spp=3, strips=[bytes(48)], extra={273: (LONG, [100000])}), OT, "truncated or corrupt")
    emit("tiff/truncated-deflate.tif", tiff(4, 4, spp=3, strips=[deflate(gradient(4, 4, 3))[:10]], compression=8),
         OT, "truncated or corrupt")
    emit("tiff/corrupt-lzw.tif", tiff(4, 4, spp=3, strips=[bytes([0xff] * 30)], compression=5), OT,
         "truncated or corrupt")
    emit("tiff/corrupt-jpeg.tif", tiff(4, 4, spp=3, strips=[b"\xff\xd8" + bytes(30)], compression=7), OT, "truncated or corrupt")
    emit("tiff/unsupported-compression.tif", tiff(4, 4, spp=3, strips=[bytes(48)], compression=34712), OT, "compression 34712 is not supported")
    emit("tiff/packbits-short.tif", tiff(4, 4, spp=3, strips=[bytes([0x00, 0x05, 0xfd, 0x07])], compression=32773),
         OT, "truncated or corrupt")
    emit("tiff/tiled.tif", tiff(4, 4, spp=3, strips=[bytes(48)],
                                extra={322: (LONG, [16]), 323: (LONG, [16]), 324: (LONG, [8]), 325: (LONG, [48])}),
         OT, "tiled TIFF")
    emit("tiff/too-big-for-ortho.tif", ortho_tiff(9, 2), OT, "TIFF of 9x9 pixels, expected at most 4x4")

    # ---- Context-coded residual tiles (doc/format.md 1.8): the 3 x 3 version-0 tile and the
    # 5 x 5 version-1 and version-2 tiles in mode 2 whose bytes tests/residual_codec_test.cpp and
    # tests/residual_context_v2_test.cpp pin, version 3's (modes 3 and 4) of tests/residual_parent_mode_test.cpp,
    # and what a decoder must refuse
    context = bytes([0x50, 0x59, 0x52, 0x43, 0x03, 0x00, 0x00, 0x00, 0x00, 0x00,
                     0x7a, 0x67, 0x99, 0x8e, 0xf7, 0xcd, 0xfa, 0x19, 0x7a])
    CT = "residual-tile 3"
    emit("valid/context-3.pyrc", context, CT, "ok")
    emit("context/truncated.pyrc", context[:-1], CT, "the stream ends early")
    emit("context/trailing-byte.pyrc", context + b"\0", CT, "1 bytes after the end")
    emit("context/header-only.pyrc", context[:8], CT, "damaged stream start")
    emit("context/wrong-size.pyrc", context, "residual-tile 4", "3 samples a side, expected 4")
    emit("context/mode-2.pyrc", context[:6] + b"\x02" + context[7:], CT, "unknown kind (mode 2, version 0)")
    emit("context/version-3.pyrc", context[:7] + b"\x03" + context[8:], CT, "unknown kind (mode 0, version 3)")
    emit("context/version-4.pyrc", context[:6] + b"\x03\x04" + context[8:], CT, "unknown kind (mode 3, version 4)")
    version1 = bytes([0x50, 0x59, 0x52, 0x43, 0x05, 0x00, 0x02, 0x01, 0x00, 0x4d, 0xe4, 0x3f,
                      0xde, 0x30, 0x67, 0x74, 0xd7, 0xa7, 0x76, 0xe0, 0xfd, 0x7d, 0x80, 0x00])
    emit("valid/context-version-1-5.pyrc", version1, "residual-tile 5", "ok")
    emit("context/version-1-mode-3.pyrc", version1[:6] + b"\x03" + version1[7:], "residual-tile 5",
         "unknown kind (mode 3, version 1)")
    emit("context/version-1-truncated.pyrc", version1[:-1], "residual-tile 5", "the stream ends early")
    version2 = bytes([0x50, 0x59, 0x52, 0x43, 0x05, 0x00, 0x02, 0x02, 0x00, 0x4c, 0x08, 0xb8,
                      0x5a, 0xe5, 0xb8, 0x6a, 0xb0, 0x6c, 0xa9, 0xe6, 0x9f, 0xb7, 0x00, 0x00])
    emit("valid/context-version-2-5.pyrc", version2, "residual-tile 5", "ok")
    # The parent mode's 5 x 5 tile of tests/residual_parent_mode_test.cpp, read as a tile alone:
    # without its parent plane it cannot be decoded.
    parent = bytes([0x50, 0x59, 0x52, 0x43, 0x05, 0x00, 0x03, 0x03, 0x00, 0x42, 0x11, 0xc9,
                    0x4a, 0x7b, 0x91, 0xa4, 0xc9, 0x4b, 0x21, 0x77, 0x19, 0x43, 0x5c, 0x00])
    emit("context/version-3-alone.pyrc", parent, "residual-tile 5", "without its parent tile")
    # The same for mode 4 (steps), the 7 x 7 tile of the same test.
    steps = bytes([0x50, 0x59, 0x52, 0x43, 0x07, 0x00, 0x04, 0x03, 0x00, 0x05, 0x01, 0x15, 0x57,
                   0x56, 0x24, 0xc6, 0x88, 0xa5, 0x7a, 0x21, 0x9e, 0xde, 0x78, 0x6b, 0x06, 0xde,
                   0x00, 0x35, 0x42, 0x4d, 0xea, 0xba, 0x94, 0xb2, 0x79, 0x9b, 0x00])
    emit("context/version-3-mode-4-alone.pyrc", steps, "residual-tile 7", "without its parent tile")
    # Mode 5 (terraces), the 6 x 6 tile of tests/residual_terrace_mode_test.cpp, likewise.
    terraces = bytes([0x50, 0x59, 0x52, 0x43, 0x06, 0x00, 0x05, 0x03, 0x00, 0x0e, 0x00, 0x10, 0x66,
                      0x71, 0xe0, 0xbb, 0x9d, 0x33, 0x3f, 0x06, 0xf8, 0xa9, 0xc4, 0x4a, 0x78, 0x77,
                      0xad, 0x68, 0x1e, 0xc6, 0x00])
    emit("context/version-3-mode-5-alone.pyrc", terraces, "residual-tile 6", "without its parent tile")
    emit("context/version-3-mode-6.pyrc", parent[:6] + b"\x06" + parent[7:], "residual-tile 5",
         "unknown kind (mode 6, version 3)")
    emit("context/version-2-mode-3.pyrc", version2[:6] + b"\x03" + version2[7:], "residual-tile 5",
         "unknown kind (mode 3, version 2)")
    emit("context/version-2-truncated.pyrc", version2[:-1], "residual-tile 5", "the stream ends early")
    emit("context/magic-only.pyrc", context[:4], CT, "not a context-coded residual tile")

    # ---- DXT blobs on their own
    emit("dxt/empty.bin", b"", "dxt1 4 4", "DXT tile of 0 bytes, expected 8")
    emit("dxt/dxt1-short.bin", dxt1_block[:7], "dxt1 4 4", "DXT tile of 7 bytes, expected 8")
    emit("dxt/dxt1-long.bin", dxt1_block * 3, "dxt1 8 4", "DXT tile of 24 bytes, expected 16")
    emit("dxt/dxt5-as-dxt1-length.bin", dxt5_block, "dxt5 8 8", "DXT tile of 16 bytes, expected 64")
    emit("dxt/dxt1-odd-size.bin", dxt1_block * 2, "dxt1 5 5", "DXT tile of 16 bytes, expected 32")
    emit("dxt/zero-size-tile.bin", dxt1_block, "dxt1 0 4", "invalid DXT tile size 0x4")
    emit("dxt/giant-size-tile.bin", dxt5_block, "dxt5 1048576 1048576", "invalid DXT tile size")

    with open(os.path.join(HERE, "MANIFEST"), "w") as f:
        f.write("# path\tdecoder\texpected error fragment (\"ok\": must decode)\n")
        for relative, decoder, expected in manifest:
            f.write("%s\t%s\t%s\n" % (relative, decoder, expected))


if __name__ == "__main__":
    main()
