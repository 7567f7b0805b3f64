// ENVI's raw rasters: a data file (FILE, FILE.img, FILE.dat, FILE.bsq, ...) with a text header,
// FILE.hdr or the data file's name and ".hdr", whose first line is "ENVI", then `key = value`
// lines (a value in braces may span lines): samples, lines, bands, header offset, data type (1
// uint8, 2 int16, 3 int32, 4 float32, 5 float64, 12 uint16, 13 uint32), interleave (bsq, bil,
// bip), byte order (0 little-endian, 1 big-endian), data ignore value (nodata), and the place:
// map info = {projection, reference pixel x, y (1-based, 1.5 its centre), easting, northing, x
// size, y size[, zone, North|South], datum[, units=...][, rotation=...]}, in the CRS of
// coordinate system string = {WKT}, else of the map info's projection (Geographic Lat/Lon, UTM
// with its zone, on WGS-84, NAD83 or NAD27). Read as a raw grid (raw_grid_reader.hpp).
#pragma once
#include <optional>
#include <string>

#include "libpyramid/input/raw_grid_reader.hpp"

namespace pyramid {

// Nothing when `path` has no ENVI header beside it. Throws Error naming the header when it
// cannot be read, or names a type, layout or size this reader cannot take.
std::optional<RawGrid> enviGrid(const std::string& path);

} // namespace pyramid
