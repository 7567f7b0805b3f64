// ESRI's ASCII grids (`.asc`, GDAL's AAIGrid; whatever the name, a file whose first word is one of
// the header's keywords): a header of keyword lines (esri_grid_header.hpp: ncols, nrows, the
// lower-left corner or centre, the cell size, NODATA_value), then nrows x ncols numbers separated
// by white space, north row first. The corner and cell size place the grid in the CRS of FILE.prj
// (sidecar_georeference.hpp). Values are read as float32, each to the nearest (integers exactly
// up to 2^24), as the text is decoded once, whole, by DecodedRows (decoded_rows.hpp: in memory or
// a scratch file, on a thread of its own while the rows decoded so far are read). A value that
// is no number, or beyond float32's range, and a file that holds fewer or more values than its
// header gives, are errors naming the file (and the row and column); a header giving more values
// than the file's bytes could hold is refused as it is read, before any row is allocated.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "libpyramid/input/decoded_rows.hpp"

namespace pyramid {

// What openAsciiGrid would open, from the header alone; nothing when the file is no ASCII grid.
// Throws Error naming the file when its header cannot be read.
std::optional<RasterInfo> describeAsciiGrid(const std::string& path);
// Null when the file is no ASCII grid. Throws as describeAsciiGrid.
std::unique_ptr<DecodedRows> openAsciiGrid(const std::string& path, int cacheMegabytes);

} // namespace pyramid
