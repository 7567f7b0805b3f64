#include "libpyramid/filters/elevation_upsample.hpp"

#include <algorithm>
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

namespace {

// row[2c] = even[c] + row[2c] and row[2c + 1] = odd[c] + row[2c + 1] for c < odds, then
// row[2 odds] = even[odds] + row[2 odds]: a row's predictions added to its residuals, both
// parities in one pass over the row (a loop over every other sample cannot store in vectors).
PYRAMID_VECTOR_CLONES
void addRow(const float* even, const float* odd, int odds, float* row) {
    for (int c = 0; c < odds; ++c) {
        row[2 * c] = even[c] + row[2 * c];
        row[2 * c + 1] = odd[c] + row[2 * c + 1];
    }
    row[2 * odds] = even[odds] + row[2 * odds];
}

// The predictions of a child tile's rows, one row at a time: predictElevation's four cases,
// split by row and column parity so that the loops carry no per-sample branch or index
// arithmetic (this runs on every sample the encoder and the CPU producers touch). Each sample
// keeps predictElevation's operations in its order. Row j's predictions are computed into `even`
// (columns 0, 2 .. n + 4) and `odd` (columns 1, 3 .. n + 3), contiguously, so that the compiler
// computes several at once; then `add(j, even, odd, odds)` stores the row. Inlined into each
// caller's clones.
template <typename Add>
[[gnu::always_inline]] inline void predictRows(const float* parent, size_t parentStride, int n, int px, int py,
                                               const Add& add) {
    float weight[4][4];
    for (int dj = 0; dj < 4; ++dj) {
        for (int di = 0; di < 4; ++di) {
            weight[dj][di] = kTap[dj] * kTap[di];
        }
    }
    const int last = n + 4; // even: columns 0, 2 .. last and 1, 3 .. last - 1
    const int odds = (last + 1) / 2;
    thread_local std::vector<float> lines;
    lines.resize(2 * static_cast<size_t>(odds) + 1);
    float* even = lines.data();
    float* odd = even + odds + 1;
    for (int j = 0; j <= last; ++j) {
        const size_t y = static_cast<size_t>(j / 2 + py);
        if ((j & 1) == 0) {
            // r[c]: parent row y, column c + px (c = i / 2). Even columns are the parent's samples.
            const float* r = parent + y * parentStride + static_cast<size_t>(px);
            for (int c = 0; c < odds; ++c) {
                odd[c] = interpolate4(r[c - 1], r[c], r[c + 1], r[c + 2]);
            }
            add(j, r, odd, odds);
            continue;
        }
        // p[d][c]: parent row y - 1 + d, column c + px.
        const float* p[4];
        for (int d = 0; d < 4; ++d) {
            p[d] = parent + (y + static_cast<size_t>(d) - 1) * parentStride + static_cast<size_t>(px);
        }
        for (int c = 0; c <= odds; ++c) {
            even[c] = interpolate4(p[0][c], p[1][c], p[2][c], p[3][c]);
        }
        for (int c = 0; c < odds; ++c) {
            float z = 0.0f;
            for (int dj = 0; dj < 4; ++dj) {
                for (int di = 0; di < 4; ++di) {
                    z = z + weight[dj][di] * p[dj][c + di - 1];
                }
            }
            odd[c] = z;
        }
        add(j, even, odd, odds);
    }
}

// addRow with the residuals read as stored: row[i] = prediction + float(r[i]) * scale for
// i < columns, prediction + 0 beyond (both rounded as upsampleAndAdd's sum of the served value).
PYRAMID_VECTOR_CLONES
void addResidualRow(const float* even, const float* odd, int odds, const int16_t* r, int columns, float scale,
                    float* row) {
    const int pairs = std::min(odds, columns / 2);
    for (int c = 0; c < pairs; ++c) {
        row[2 * c] = even[c] + static_cast<float>(r[2 * c]) * scale;
        row[2 * c + 1] = odd[c] + static_cast<float>(r[2 * c + 1]) * scale;
    }
    for (int i = 2 * pairs; i <= 2 * odds; ++i) {
        const float served = i < columns ? static_cast<float>(r[i]) * scale : 0.0f;
        row[i] = ((i & 1) != 0 ? odd[i / 2] : even[i / 2]) + served;
    }
}

} // namespace

PYRAMID_VECTOR_CLONES
void upsampleAndAdd(const float* parent, size_t parentStride, int n, int px, int py, float* out,
                    size_t outStride) {
    predictRows(parent, parentStride, n, px, py, [&](int j, const float* even, const float* odd, int odds) {
        addRow(even, odd, odds, out + static_cast<size_t>(j) * outStride);
    });
}

PYRAMID_VECTOR_CLONES
void upsampleAndAddResiduals(const float* parent, size_t parentStride, int n, int px, int py,
                             const ResidualWindow& r, float* out, size_t outStride) {
    predictRows(parent, parentStride, n, px, py, [&](int j, const float* even, const float* odd, int odds) {
        const bool stored = j < r.rows && r.columns > 0;
        addResidualRow(even, odd, odds, stored ? r.first + static_cast<size_t>(j) * r.stride : nullptr,
                       stored ? r.columns : 0, r.scale, out + static_cast<size_t>(j) * outStride);
    });
}

} // namespace pyramid
