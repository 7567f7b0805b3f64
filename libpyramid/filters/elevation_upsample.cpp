#include "libpyramid/filters/elevation_upsample.hpp"

#include <vector>

#include "formats/vector_clones.hpp"

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

PYRAMID_VECTOR_CLONES
void upsampleAndAdd(const float* parent, size_t parentStride, int n, int px, int py, float* out,
                    size_t outStride) {
    // predictElevation's four cases, split by row and column parity so that the loops carry no
    // per-sample branch or index arithmetic (this runs on every sample the encoder and the CPU
    // producers touch). Each sample keeps predictElevation's operations in its order.
    float weight[4][4];
    for (int dj = 0; dj < 4; ++dj) {
        for (int di = 0; di < 4; ++di) {
            weight[dj][di] = kTap[dj] * kTap[di];
        }
    }
    const int last = n + 4;
    // Odd columns (i = 2c + 1 <= last) are computed into `line` first, contiguously, so that the
    // compiler computes several at once (each still with its own operations in order), then
    // added to every other sample of the row.
    const int odd = (last + 1) / 2;
    thread_local std::vector<float> line;
    line.resize(static_cast<size_t>(odd));
    for (int j = 0; j <= last; ++j) {
        float* row = out + static_cast<size_t>(j) * outStride;
        const size_t y = static_cast<size_t>(j / 2 + py);
        if ((j & 1) == 0) {
            // r[c]: parent row y, column c + px (c = i / 2).
            const float* r = parent + y * parentStride + static_cast<size_t>(px);
            for (int i = 0; i <= last; i += 2) {
                row[i] = r[i / 2] + row[i];
            }
            for (int c = 0; c < odd; ++c) {
                line[static_cast<size_t>(c)] = interpolate4(r[c - 1], r[c], r[c + 1], r[c + 2]);
            }
            for (int c = 0; c < odd; ++c) {
                row[2 * c + 1] = line[static_cast<size_t>(c)] + row[2 * c + 1];
            }
            continue;
        }
        // p[d][c]: parent row y - 1 + d, column c + px.
        const float* p[4];
        for (int d = 0; d < 4; ++d) {
            p[d] = parent + (y + static_cast<size_t>(d) - 1) * parentStride + static_cast<size_t>(px);
        }
        for (int i = 0; i <= last; i += 2) {
            const int c = i / 2;
            row[i] = interpolate4(p[0][c], p[1][c], p[2][c], p[3][c]) + row[i];
        }
        for (int c = 0; c < odd; ++c) {
            float z = 0.0f;
            for (int dj = 0; dj < 4; ++dj) {
                for (int di = 0; di < 4; ++di) {
                    z = z + weight[dj][di] * p[dj][c + di - 1];
                }
            }
            line[static_cast<size_t>(c)] = z;
        }
        for (int c = 0; c < odd; ++c) {
            row[2 * c + 1] = line[static_cast<size_t>(c)] + row[2 * c + 1];
        }
    }
}

} // namespace pyramid
