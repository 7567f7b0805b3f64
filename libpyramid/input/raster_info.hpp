// What every raster reader reports of its input, and the sample types they read: the
// vocabulary shared by the readers (TIFF, PNG, the image I/O module) and the dispatcher
// (raster_source.hpp) that stands above them.
#pragma once
#include <cmath>
#include <optional>
#include <string>

#include "libpyramid/input/georeference.hpp"

namespace pyramid {

enum class SampleType { UInt8, Int8, UInt16, Int16, UInt32, Int32, Float16, Float32, Float64, Other };

// "uint8", "int16", "float32", ...: for reports.
const char* sampleTypeName(SampleType type);

struct RasterInfo {
    int width = 0;
    int height = 0;
    int channels = 0;
    SampleType type = SampleType::Other;
    std::optional<double> nodata; // declared by the file (GDAL_NODATA, ...), if any
    std::string formatName;       // "tiff", "png", ...
    std::optional<Georeference> georeference; // a GeoTIFF's CRS and pixel-to-CRS transform, if any
};

// Whether a sample, read as float32, is the declared nodata: equal to it in float32 (the value
// as the readers deliver it), or NaN when the nodata is NaN.
inline bool isNodata(float v, const std::optional<double>& nodata) {
    return nodata && (v == static_cast<float>(*nodata) || (std::isnan(*nodata) && std::isnan(v)));
}

} // namespace pyramid
