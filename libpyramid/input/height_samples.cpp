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
    const std::string at = " at column " + std::to_string(place.column) + ", row " + std::to_string(place.row);
    if (!std::isnan(s) && source.info().type == SampleType::Float64) {
        // Heights are float32: a finite 64-bit value past its range reads as an infinity too.
        const bool up = s > 0.0f;
        fail(place.path, std::string(up ? "+Inf, or a height above 3.4e38," : "-Inf, or a height below -3.4e38,") + at +
                             ": heights are read as float32, whose range ends there (declare " + (up ? "inf" : "-inf") +
                             " the nodata value only if infinities mean missing)");
    }
    const char* what = std::isnan(s) ? "NaN" : s > 0.0f ? "+Inf" : "-Inf";
    const char* declare = std::isnan(s) ? "NaN" : s > 0.0f ? "inf" : "-inf";
    fail(place.path, std::string(what) + " height" + at + " (declare " + declare +
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
