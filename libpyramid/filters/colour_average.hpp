// Ortho mipmaps: each coarser level is the 2x2 average of the level below, computed in a
// linear space and rounded to 8 bits at every level (doc/ortho-encoding.md, "Levels").
//
// With sRGB averaging (the default) the colour channels are decoded from sRGB to linear light
// through a table of 16-bit integers, averaged, and encoded back to the nearest 8-bit sRGB
// value; the alpha-like last channel of 2- and 4-channel images is averaged as stored. All
// arithmetic is on integers, so every machine computes the same bytes.
#pragma once
#include <cstdint>

#include "libpyramid/filters/image8.hpp"

namespace pyramid {

enum class ColourSpace { Srgb, Linear };

class ColourAverager {
public:
    ColourAverager(ColourSpace space, int channels);
    // The average of four 8-bit values of channel `channel`.
    uint8_t average(int channel, uint8_t a, uint8_t b, uint8_t c, uint8_t d) const;
    // Half-size image: output pixel (x, y) averages input (2x..2x+1, 2y..2y+1). Even sizes.
    Image8 reduce(const Image8& in) const;

private:
    bool linearChannel(int channel) const;
    ColourSpace space_;
    int channels_;
};

} // namespace pyramid
