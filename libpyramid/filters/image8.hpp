// The 8-bit images the ortho side computes with: the colour averages' input and output, the
// true tiles of the ortho encoder.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "libpyramid/filters/pixel_memory.hpp"

namespace pyramid {

using PixelBytes = std::vector<uint8_t, DefaultInitAllocator<uint8_t>>;

// An 8-bit image, row-major, row 0 = bottom (south).
struct Image8 {
    // The constructor's pixels: 0, or left as they come (every pixel is written next).
    enum Fill { Zeros, Unset };
    int width = 0, height = 0, channels = 0;
    PixelBytes pixels;
    Image8() = default;
    Image8(int w, int h, int c, Fill fill = Zeros)
        : width(w), height(h), channels(c) {
        const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(c);
        if (fill == Zeros) {
            pixels.assign(n, 0);
        } else {
            pixels.resize(n);
        }
    }
    uint8_t* at(int x, int y) {
        return &pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * static_cast<size_t>(channels)];
    }
    const uint8_t* at(int x, int y) const {
        return &pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * static_cast<size_t>(channels)];
    }
};

} // namespace pyramid
