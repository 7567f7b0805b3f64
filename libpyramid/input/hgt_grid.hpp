// SRTM height files (`.hgt`): a square of N x N big-endian int16 heights in metres, north row
// first, nothing else in the file (N = 1201 for 3 arc-second cells, 3601 for 1 arc-second ones;
// any N from 2 whose 2 N^2 bytes are the file's size is taken). The file's name places it: its
// stem begins with the south-west corner of its 1 x 1 degree cell, `N46W122` (latitude 46 N,
// longitude 122 W; case ignored). The samples are points on the degree lines and between them,
// the edge rows and columns on the cell's edges (so neighbouring files share them): PixelIsPoint,
// one sample every 1 / (N - 1) degree, on WGS 84. -32768 marks a void (nodata). Read as a raw
// grid (raw_grid_reader.hpp).
#pragma once
#include <optional>
#include <string>

#include "libpyramid/input/raw_grid_reader.hpp"

namespace pyramid {

// Nothing when `path` is not named as a height file (`.hgt`, any case). Throws Error naming the
// file when it is so named but its name places no cell or its size is no square of int16.
std::optional<RawGrid> hgtGrid(const std::string& path);

} // namespace pyramid
