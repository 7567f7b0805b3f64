// USGS's ASCII DEM format (`.dem`, the Digital Elevation Model standard of USGS's National Mapping
// Program: 7.5-minute, 30-minute and 1-degree DEMs, and GDAL's USGSDEM writer): an A record of
// fixed fields (1024 bytes), then one B record per profile, a column of elevations south to
// north, the profiles west to east; a C record of accuracy may follow.
//
// The A record gives the planimetric reference system (0 geographic, its coordinates in seconds
// of arc; 1 UTM with its zone, negative in the southern hemisphere; others are left to the
// sidecars), the horizontal datum (NAD27, WGS 84 or NAD83: datum_epsg.hpp; WGS 72 and the rest
// unplaced), the units of the elevations (feet or metres: the height unit), the spatial
// resolution (x, y, z) and the number of profiles. Each B record gives its first elevation's
// ground coordinates, the local datum elevation and its count of elevations, integers (the
// numbers may run into each other where a sign follows a digit); an elevation is the datum
// elevation plus the integer times the z resolution, and -32767 is a void. The profiles of a
// UTM quadrangle start and end at different rows: the grid spans them all, its cells the posts
// (PixelIsPoint), and a cell no profile covers is a void. Voids are NaN, declared as nodata.
//
// The records are read as numbers separated by blanks, whether blocked in 1024-byte records or
// written a line at a time. The profiles come column by column, so the grid is decoded whole,
// into memory (refused, naming the cache it needs, beyond the input cache: such files are small).
// A file is taken as a USGS DEM by its name (`.dem`, any case) and an A record whose codes make
// sense; a GTOPO30 `.dem` (binary, with a `.hdr`) is left to the raw grid reader.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "libpyramid/input/decoded_rows.hpp"

namespace pyramid {

// What openUsgsDem would open, from the A record and the profiles' headers; nothing when the
// file is no USGS DEM. Throws Error naming the file when its records are damaged.
std::optional<RasterInfo> describeUsgsDem(const std::string& path);
// Null when the file is no USGS DEM. Throws as describeUsgsDem, and
// OptionError("cacheMegabytes") when the grid exceeds the input cache.
std::unique_ptr<DecodedRows> openUsgsDem(const std::string& path, int cacheMegabytes);

} // namespace pyramid
