// Gridded XYZ text (`.xyz`, any case; GDAL's XYZ), as many national mapping agencies ship their
// lidar terrain models: one line per cell, its centre's x and y and its height, separated by
// spaces, tabs, commas or semicolons, after an optional header line naming the columns (`x`,
// `lon`, `east...` / `y`, `lat`, `north...` / `z`, `alt`, `height`, `elev...`; else the first three
// columns). The lines come a row at a time: the lines of one y together, x increasing; the rows
// north to south or south to north. The spacing is the smallest step between neighbours, and
// cells without a line (gaps, a coast) are nodata: NaN, declared whenever a cell is missing or a
// height is written as `nan` (else the PAM file's nodata, if any, as for any raster). Placed in
// the CRS of FILE.prj or the PAM file's `<SRS>`, as an ESRI grid is.
//
// Read in two passes: the first finds the rows (each one's y and bytes) and the grid, without
// parsing the heights; the second parses each row's lines once, north first, into DecodedRows
// (decoded_rows.hpp: in memory within the input cache, else a scratch file). Errors naming the file
// and the line: a line of fewer than three numbers, x not increasing along a row, rows out of
// order, a point off the grid, a height beyond float32's range; a file sorted by x (a column at a
// time), and points too sparse to be a grid (under 1/64 of its cells), are refused.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "libpyramid/input/decoded_rows.hpp"

namespace pyramid {

// What openXyzGrid would open, from the first pass; nothing when the file is not named `.xyz`.
// Throws Error naming the file (and the line) when it is no regular grid.
std::optional<RasterInfo> describeXyzGrid(const std::string& path);
// Null when the file is not named `.xyz`. Throws as describeXyzGrid.
std::unique_ptr<DecodedRows> openXyzGrid(const std::string& path, int cacheMegabytes);

} // namespace pyramid
