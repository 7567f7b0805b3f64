// ERDAS Imagine files (HFA, `.img`; whatever the name, a file that begins with
// `EHFA_HEADER_TAG`), as USGS's National Elevation Dataset and many GIS tools ship DEMs and
// imagery: a tree of nodes (hfa_file.hpp), each of a type the file's own dictionary lays out
// (hfa_dictionary.hpp). The root's `Eimg_Layer` nodes are the bands, all of one size and pixel
// type (1 for a DEM, 3 or 4 for imagery); each holds its pixels in blocks (`RasterDMS`,
// hfa_blocks.hpp), its nodata (`Eimg_NonInitializedValue`) and its placement:
//   - `Map_Info`: the upper-left pixel's centre and the pixel size, in the CRS of
//   - `ProjectionX`'s ESRI WKT (what ArcGIS and GDAL write), else `Projection` and its `Datum`:
//     geographic or UTM (its zone, the hemisphere by the sign of the fourth parameter) on WGS 84,
//     NAD83 or NAD27 (datum_epsg.hpp); another CRS leaves the file to its sidecars.
// A layer kept in a spill file (`ExternalRasterDMS`, `.ige`) is read from it (hfa_spill.hpp).
// Layers that differ in size or type and complex pixels are refused naming the file.
//
// The blocks are read a row of blocks at a time (one pread a block and band), decoded, and
// given whole, north first, to DecodedRows (decoded_rows.hpp: in memory within the input cache,
// else a scratch file). A block the file never wrote is nodata, or 0 without one.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include "libpyramid/input/decoded_rows.hpp"

namespace pyramid {

// What openHfa would open, from the file's nodes alone; nothing when the file is no ERDAS
// Imagine file. Throws Error naming the file when its structure is damaged or cannot be read.
std::optional<RasterInfo> describeHfa(const std::string& path);
// Null when the file is no ERDAS Imagine file. Throws as describeHfa.
std::unique_ptr<DecodedRows> openHfa(const std::string& path, int cacheMegabytes);

} // namespace pyramid
