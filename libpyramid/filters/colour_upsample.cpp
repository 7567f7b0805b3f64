#include "libpyramid/filters/colour_upsample.hpp"

#include <vector>

#include "libpyramid/support/vector_clones.hpp"

namespace pyramid {

namespace {

// The parent rows by and by + 1 blended with weights wy0 and wy1 (at most 4 x 255 x 4 = 4080):
// `count` samples.
PYRAMID_VECTOR_CLONES
void blendRows(const uint8_t* __restrict r0, const uint8_t* __restrict r1, unsigned wy0, unsigned wy1, size_t count,
               uint16_t* __restrict out) {
    for (size_t k = 0; k < count; ++k) {
        out[k] = static_cast<uint16_t>(wy0 * r0[k] + wy1 * r1[k]);
    }
}

// Child pixels x = 0..side-1 from the blended parent row `v` (parent column j at v[j * C]):
// x even (x = 2m) takes columns (m + rx, m + rx + 1) with weights (1, 3), x odd (x = 2m - 1)
// takes (m + rx, m + rx + 1) with weights (3, 1).
template <int C>
void predictFromBlend(const uint16_t* __restrict v, int rx, int side, uint8_t* __restrict out) {
    for (int x = 0; x < side; ++x) {
        const int bx = (x + 1) / 2 + rx;
        const unsigned wx0 = (x & 1) ? 3u : 1u;
        const unsigned wx1 = 4u - wx0;
        for (int c = 0; c < C; ++c) {
            const unsigned sum = wx0 * v[bx * C + c] + wx1 * v[(bx + 1) * C + c];
            out[x * C + c] = static_cast<uint8_t>(sum >> 4);
        }
    }
}

} // namespace

void predictColourRow(const uint8_t* parent, size_t rowBytes, int channels, int rx, int ry, int y, int side,
                     uint8_t* out) {
    const size_t by = static_cast<size_t>((y + 1) / 2 + ry);
    const unsigned wy0 = (y & 1) ? 3u : 1u;
    thread_local std::vector<uint16_t> blended;
    blended.resize(rowBytes);
    blendRows(parent + by * rowBytes, parent + (by + 1) * rowBytes, wy0, 4u - wy0, rowBytes, blended.data());
    switch (channels) {
    case 1: return predictFromBlend<1>(blended.data(), rx, side, out);
    case 2: return predictFromBlend<2>(blended.data(), rx, side, out);
    case 3: return predictFromBlend<3>(blended.data(), rx, side, out);
    default: return predictFromBlend<4>(blended.data(), rx, side, out);
    }
}

uint8_t predictColour(const uint8_t* parent, size_t rowBytes, int channels, int channel, int rx, int ry,
                     int x, int y) {
    const size_t bx = static_cast<size_t>((x + 1) / 2 + rx);
    const size_t by = static_cast<size_t>((y + 1) / 2 + ry);
    // Weight of the bx column (the bx+1 column gets 4 minus it), likewise for rows.
    const unsigned wx0 = (x & 1) ? 3u : 1u;
    const unsigned wy0 = (y & 1) ? 3u : 1u;
    const unsigned wx1 = 4u - wx0;
    const unsigned wy1 = 4u - wy0;
    const size_t c = static_cast<size_t>(channels);
    const uint8_t* r0 = parent + by * rowBytes + static_cast<size_t>(channel);
    const uint8_t* r1 = r0 + rowBytes;
    const unsigned sum = wy0 * (wx0 * r0[bx * c] + wx1 * r0[(bx + 1) * c]) +
                         wy1 * (wx0 * r1[bx * c] + wx1 * r1[(bx + 1) * c]);
    return static_cast<uint8_t>(sum >> 4);
}

void upsampleColour(const uint8_t* parent, int tileSize, int channels, int tx, int ty,
                   const uint8_t* residual, uint8_t* out) {
    const int side = tileSize + 4;
    const size_t rowBytes = static_cast<size_t>(side) * static_cast<size_t>(channels);
    const int rx = (tx & 1) * (tileSize / 2);
    const int ry = (ty & 1) * (tileSize / 2);
    for (int y = 0; y < side; ++y) {
        uint8_t* row = out + static_cast<size_t>(y) * rowBytes;
        predictColourRow(parent, rowBytes, channels, rx, ry, y, side, row);
        if (residual) { // without, every stored value is 128: the prediction itself
            const uint8_t* stored = residual + static_cast<size_t>(y) * rowBytes;
            for (size_t k = 0; k < rowBytes; ++k) {
                row[k] = applyColourResidual(row[k], stored[k]);
            }
        }
    }
}

} // namespace pyramid
