// The 8-bit images the ortho side computes with: the colour averages' input and output, the
// true tiles of the ortho encoder.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pyramid {

// An 8-bit image, row-major, row 0 = bottom (south).
struct Image8 {
    int width = 0, height = 0, channels = 0;
    std::vector<uint8_t> pixels;
    Image8() = default;
    Image8(int w, int h, int c)
        : width(w), height(h), channels(c), pixels(static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(c)) {}
    uint8_t* at(int x, int y) {
        return &pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * static_cast<size_t>(channels)];
    }
    const uint8_t* at(int x, int y) const {
        return &pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * static_cast<size_t>(channels)];
    }
};

} // namespace pyramid
