#include "tests/support/ortho_images.hpp"

#include <cmath>

namespace pyramid::test {

std::vector<uint16_t> orthoImage(int w, int h, int channels, int maxValue) {
    std::vector<uint16_t> v(static_cast<size_t>(w) * h * channels);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < channels; ++c) {
                const double s = 0.5 + 0.45 * std::sin(x / (7.0 + c) + y / 11.0) * std::cos((x - y) / 13.0);
                v[(static_cast<size_t>(y) * w + x) * channels + c] =
                    static_cast<uint16_t>(std::lround(s * maxValue + ((x * 7 + y * 3 + c) % 5)));
            }
        }
    }
    return v;
}

OrthoEncodeOptions smallOrtho() {
    OrthoEncodeOptions o;
    o.levels.tileSize = 16;
    return o;
}

} // namespace pyramid::test
