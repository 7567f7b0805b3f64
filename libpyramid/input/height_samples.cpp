#include "libpyramid/input/height_samples.hpp"

#include "formats/error.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

HeightSamples::HeightSamples(std::optional<double> nodata)
    : nodata_(nodata.has_value()), nanNodata_(nodata && std::isnan(*nodata)),
      finiteNodata_(nodata && std::isfinite(static_cast<float>(*nodata))),
      value_(nodata && !std::isnan(*nodata) ? static_cast<float>(*nodata) : 0.0f) {}

void HeightSamples::failNotFinite(float s, const RasterSource& source, int64_t x, int64_t y, int channel) {
    const RasterSource::PixelPlace place = source.placeOf(static_cast<int>(x), static_cast<int>(y), channel);
    const char* what = std::isnan(s) ? "NaN" : s > 0.0f ? "+Inf" : "-Inf";
    const char* declare = std::isnan(s) ? "NaN" : s > 0.0f ? "inf" : "-inf";
    fail(place.path, std::string(what) + " height at column " + std::to_string(place.column) + ", row " +
                         std::to_string(place.row) + " (declare " + declare +
                         " the nodata value to treat it as missing)");
}

std::string nodataText(double value) {
    if (std::isnan(value)) {
        return "nan";
    }
    if (std::isinf(value)) {
        return value > 0.0 ? "inf" : "-inf";
    }
    return numberText(value);
}

} // namespace pyramid
