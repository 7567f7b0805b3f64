#!/usr/bin/python3
"""Writes the browser test's cone: a square float32 TIFF (one strip, no compression, no
georeference) of N x N heights, a cone of the given height and radius (in samples) in the
middle, 0 around it. preprocessDem reads it like any TIFF.

  make_cone.py cone.tif [--size 385] [--height 120] [--radius 150]
"""

import argparse
import array
import math
import struct
import sys


def cone(size, height, radius):
    c = (size - 1) / 2
    heights = array.array("f")
    for y in range(size):
        for x in range(size):
            heights.append(max(0.0, height * (1 - math.hypot(x - c, y - c) / radius)))
    return heights


def tiff(path, size, heights):
    if sys.byteorder != "little":
        heights.byteswap()
    data = heights.tobytes()
    entries = [  # tag, type (3 SHORT, 4 LONG), value
        (256, 4, size), (257, 4, size), (258, 3, 32), (259, 3, 1), (262, 3, 1),
        (273, 4, 0), (277, 3, 1), (278, 4, size), (279, 4, len(data)), (284, 3, 1), (339, 3, 3),
    ]
    ifd_offset = 8
    data_offset = ifd_offset + 2 + 12 * len(entries) + 4
    ifd = struct.pack("<H", len(entries))
    for tag, kind, value in entries:
        value = data_offset if tag == 273 else value
        packed = struct.pack("<HH", value, 0) if kind == 3 else struct.pack("<I", value)
        ifd += struct.pack("<HHI", tag, kind, 1) + packed
    ifd += struct.pack("<I", 0)
    with open(path, "wb") as f:
        f.write(b"II*\0" + struct.pack("<I", ifd_offset) + ifd + data)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("output")
    parser.add_argument("--size", type=int, default=385)
    parser.add_argument("--height", type=float, default=120)
    parser.add_argument("--radius", type=float, default=150)
    args = parser.parse_args()
    tiff(args.output, args.size, cone(args.size, args.height, args.radius))


if __name__ == "__main__":
    main()
