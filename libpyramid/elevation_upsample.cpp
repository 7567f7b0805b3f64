#include "libpyramid/elevation_upsample.hpp"

namespace pyramid {

namespace {
// Weights of the centre (odd, odd) samples, indexed by the tap -1..2 (+1).
constexpr float kTap[4] = {-1.0f / 16.0f, 9.0f / 16.0f, 9.0f / 16.0f, -1.0f / 16.0f};
} // namespace

float predictElevation(const float* parent, size_t stride, int px, int py, int i, int j) {
    const size_t x = static_cast<size_t>(i / 2 + px);
    const size_t y = static_cast<size_t>(j / 2 + py);
    const bool oddI = (i & 1) != 0;
    const bool oddJ = (j & 1) != 0;
    if (!oddI && !oddJ) {
        return parent[x + y * stride];
    }
    if (oddI && !oddJ) {
        const float* row = parent + y * stride;
        return interpolate4(row[x - 1], row[x], row[x + 1], row[x + 2]);
    }
    if (!oddI && oddJ) {
        return interpolate4(parent[x + (y - 1) * stride], parent[x + y * stride],
                            parent[x + (y + 1) * stride], parent[x + (y + 2) * stride]);
    }
    // Centre: a sum from 0, rows dj = -1..2 outside, columns di = -1..2 inside, each term
    // (wj * wi) * p. The weight products are exact (multiples of 1/256).
    float z = 0.0f;
    for (int dj = 0; dj < 4; ++dj) {
        const float* row = parent + (y + static_cast<size_t>(dj) - 1) * stride;
        for (int di = 0; di < 4; ++di) {
            z = z + (kTap[dj] * kTap[di]) * row[x + static_cast<size_t>(di) - 1];
        }
    }
    return z;
}

void upsampleAndAdd(const float* parent, size_t parentStride, int n, int px, int py, float* out,
                    size_t outStride) {
    for (int j = 0; j <= n + 4; ++j) {
        float* row = out + static_cast<size_t>(j) * outStride;
        for (int i = 0; i <= n + 4; ++i) {
            row[i] = predictElevation(parent, parentStride, px, py, i, j) + row[i];
        }
    }
}

} // namespace pyramid
