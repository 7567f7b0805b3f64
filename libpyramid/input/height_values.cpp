#include "libpyramid/input/height_values.hpp"

#include "formats/error.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

void HeightConversion::apply(float* samples, int x0, int y0, int x1, int y1, const std::optional<double>& nodata,
                             const std::string& path) const {
    if (identity()) {
        return;
    }
    // (stored x scale + offset) x unit, the offset added only where there is one (so that -0
    // stays -0, as the unit alone leaves it).
    const auto width = static_cast<size_t>(x1 - x0);
    const size_t count = width * static_cast<size_t>(y1 - y0);
    for (size_t k = 0; k < count; ++k) {
        if (isNodata(samples[k], nodata)) {
            continue;
        }
        double v = static_cast<double>(samples[k]) * values.scale;
        if (values.offset != 0.0) {
            v += values.offset;
        }
        const auto height = static_cast<float>(v * unit);
        if (isNodata(height, nodata)) {
            fail(path, "the sample " + numberText(samples[k]) + " at pixel (" +
                           std::to_string(x0 + static_cast<int>(k % width)) + ", " +
                           std::to_string(y0 + static_cast<int>(k / width)) + ") is the height " + numberText(height) +
                           ", the nodata value: its scale, offset or unit maps a value onto it");
        }
        samples[k] = height;
    }
}

} // namespace pyramid
