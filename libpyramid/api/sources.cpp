#include "libpyramid/api/sources.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "formats/error.hpp"

namespace pyramid {

namespace {

size_t product(int a, int b, int c = 1) {
    return static_cast<size_t>(a) * static_cast<size_t>(b) * static_cast<size_t>(c);
}

void checkShape(const std::string& name, size_t given, int width, int height, int channels) {
    if (width < 1 || height < 1) {
        fail(name, "an image of " + std::to_string(width) + " x " + std::to_string(height) + " samples");
    }
    if (given != product(width, height, channels)) {
        fail(name, std::to_string(given) + " values for " + std::to_string(width) + " x " + std::to_string(height) +
                       (channels > 1 ? " x " + std::to_string(channels) : std::string()) + " samples");
    }
}

} // namespace

ElevationArray::ElevationArray(std::span<const float> heights, int width, int height, std::optional<double> nodata,
                               std::string name)
    : heights_(heights), width_(width), height_(height), nodata_(nodata), name_(std::move(name)) {
    checkShape(name_, heights.size(), width, height, 1);
}

void ElevationArray::read(int x0, int y0, int x1, int y1, float* out) const {
    const size_t w = static_cast<size_t>(x1 - x0);
    for (int y = y0; y < y1; ++y) {
        std::copy_n(heights_.data() + product(y, width_) + static_cast<size_t>(x0), w, out);
        out += w;
    }
}

ColourArray::ColourArray(std::span<const uint8_t> pixels, int width, int height, int channels, std::string name)
    : pixels_(pixels), width_(width), height_(height), channels_(channels), name_(std::move(name)) {
    if (channels < 1 || channels > 4) {
        fail(name_, std::to_string(channels) + " channels, not 1 to 4");
    }
    checkShape(name_, pixels.size(), width, height, channels);
}

void ColourArray::read(int x0, int y0, int x1, int y1, uint8_t* out) const {
    const size_t row = product(x1 - x0, channels_);
    for (int y = y0; y < y1; ++y) {
        std::copy_n(pixels_.data() + product(y, width_, channels_) + product(x0, channels_), row, out);
        out += row;
    }
}

PlanetFunction::PlanetFunction(std::function<double(double, double)> value, int resolution, std::string name)
    : value_(std::move(value)), resolution_(resolution), name_(std::move(name)) {
    if (!value_) {
        fail(name_, "no function");
    }
    if (resolution < 4) {
        fail(name_, "a resolution of " + std::to_string(resolution) + " samples around the equator, below 4");
    }
}

void PlanetFunction::read(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const {
    for (size_t k = 0; k < count; ++k) {
        out[k] = static_cast<float>(value_(points[k].latitude, points[k].longitude));
        valid[k] = 1;
    }
}

} // namespace pyramid
