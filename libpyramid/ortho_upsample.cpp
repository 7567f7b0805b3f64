#include "libpyramid/ortho_upsample.hpp"

namespace pyramid {

uint8_t predictOrtho(const uint8_t* parent, size_t rowBytes, int channels, int channel, int rx, int ry,
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

void upsampleOrtho(const uint8_t* parent, int tileSize, int channels, int tx, int ty,
                   const uint8_t* residual, uint8_t* out) {
    const int side = tileSize + 4;
    const size_t rowBytes = static_cast<size_t>(side) * static_cast<size_t>(channels);
    const int rx = (tx & 1) * (tileSize / 2);
    const int ry = (ty & 1) * (tileSize / 2);
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            for (int ch = 0; ch < channels; ++ch) {
                const size_t k = static_cast<size_t>(y) * rowBytes + static_cast<size_t>(x * channels + ch);
                const uint8_t p = predictOrtho(parent, rowBytes, channels, ch, rx, ry, x, y);
                out[k] = applyColourResidual(p, residual ? residual[k] : uint8_t{128});
            }
        }
    }
}

} // namespace pyramid
