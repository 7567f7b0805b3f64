// Heights as a file's values, the one rule of RasterSource::readFloat: a stored sample times its
// channel's scale plus its offset (GDAL's band metadata: gdal_band_metadata.hpp), converted to the
// ground's unit where the file's heights are in another (height_unit.hpp), in double and rounded
// to float32 once. The file's nodata value is kept as stored, so that every reader of heights
// (the encoders, mosaics, planets, `pyramid verify`) finds its gaps by the value the file declares.
#pragma once
#include <optional>
#include <string>

#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

struct HeightConversion {
    ValueScaling values;
    double unit = 1.0; // Georeference::heightsToGround

    bool identity() const { return values.identity() && unit == 1.0; }
    // Converts the samples of a window read from `path` in place (rows of x1 - x0 from (x0, y0),
    // row-major): every sample but `nodata`. Throws (fail, naming the file and the pixel) where a
    // sample's height is the nodata value, which would then be taken for a gap.
    void apply(float* samples, int x0, int y0, int x1, int y1, const std::optional<double>& nodata,
               const std::string& path) const;
};

} // namespace pyramid
