// What a TIFF input holds, read with libtiff alone (no OpenImageIO): size, channels, sample
// type, GDAL's nodata tag and the GeoTIFF georeferencing (georeference.hpp).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

// The description of a TIFF whose first image stores its samples as they are: grey
// (min-is-black) or RGB, interleaved (or one band), of 8, 16, 32 or 64-bit integers or
// floats that libtiff can decode. That is the description OpenImageIO gives of such a file
// (format "tiff"). Nullopt for anything else (not a TIFF, palette, YCbCr, CMYK, separate
// planes, 1-bit, half floats, an unknown compression...), which is left to OpenImageIO.
std::optional<RasterInfo> readPlainTiffInfo(const std::string& path);

// GDAL's band metadata (gdal_band_metadata.hpp) of the TIFF at `path`, added to its description:
// the channels' scaling, and the heights' unit where the GeoKeys name none (UNITTYPE). Throws on
// a tag that cannot be read.
void addGdalBandMetadata(RasterInfo& info, const std::string& path);
// The heights' unit by a UNITTYPE, where the file is georeferenced and its GeoKeys name none.
void addUnitType(RasterInfo& info, const std::string& unitType);

// The nodata value of GDAL's ASCII tag 42113, if the file is a TIFF that has one.
std::optional<double> geoTiffNodata(const std::string& path);

// A tag of an open TIFF (libtiff's TIFF*) as doubles, shorts or text, however libtiff holds it:
// registered (its own tags, or GeoTIFF's when libgeotiff registered them in this process) or as
// an anonymous field (read with a count before the pointer). Empty / nullopt when absent.
std::vector<double> tiffDoubles(void* tif, uint32_t tag);
std::vector<uint16_t> tiffShorts(void* tif, uint32_t tag);
std::optional<std::string> tiffText(void* tif, uint32_t tag);

} // namespace pyramid
