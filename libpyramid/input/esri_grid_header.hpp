// ESRI's grid headers: keyword lines, one keyword and its value each, any case.
//   - The .hdr-labelled raw grids ("ESRI BIL"): FILE.bil, .bip, .bsq, .flt, GTOPO30's .dem, ...
//     with FILE.hdr beside it (NROWS, NCOLS, NBANDS, NBITS, PIXELTYPE, BYTEORDER, LAYOUT,
//     SKIPBYTES, BANDROWBYTES, TOTALROWBYTES, BANDGAPBYTES, NODATA; ULXMAP, ULYMAP, XDIM, YDIM, or
//     a .flt header's xllcorner, yllcorner, cellsize, byteorder LSBFIRST), read as GDAL's EHdr
//     driver reads them: what a header leaves out is what GDAL takes (BIL, 8 bits, big-endian;
//     without NBITS or PIXELTYPE, the type of the file's size per sample; a .flt's float32; a
//     negative NODATA's signed integers). Read as a raw grid (raw_grid_reader.hpp).
//   - The ASCII grid's header (ascii_grid_reader.hpp): ncols, nrows, xllcorner or xllcenter,
//     yllcorner or yllcenter, cellsize (or dx and dy), NODATA_value.
// The corner and cell size place the grid in the CRS of FILE.prj (sidecar_georeference.hpp).
#pragma once
#include <array>
#include <map>
#include <optional>
#include <string>

#include "libpyramid/input/raw_grid_reader.hpp"

namespace pyramid {

// Lower-case keyword -> the text of its value (the first word after it).
using EsriKeys = std::map<std::string, std::string>;

// The keys' number; nothing when the keyword is not there. Throws naming `where` when its value is
// no number.
std::optional<double> esriNumber(const EsriKeys& keys, const std::string& key, const std::string& where);

// The pixels' affine map (GDAL's order: x0, dx, rx, y0, ry, dy) the keys give a grid of `rows`
// rows: ulxmap/ulymap (pixel centres), xllcorner/yllcorner or xllcenter/yllcenter (the lower-left
// pixel's corner or centre), with xdim/ydim, cellsize or dx/dy; nothing when they give no corner.
// Throws naming `where` for a cell size that is not a positive number.
std::optional<std::array<double, 6>> esriTransform(const EsriKeys& keys, int rows, const std::string& where);

// Nothing when `path` has no ESRI .hdr beside it (FILE.hdr or FILE.HDR, not ENVI's, giving
// ncols and nrows). Throws Error naming the header when it names a layout, type or size this
// reader cannot take.
std::optional<RawGrid> esriHeaderGrid(const std::string& path);

} // namespace pyramid
