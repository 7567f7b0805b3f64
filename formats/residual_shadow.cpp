#include "formats/residual_shadow.hpp"

#include <algorithm>
#include <cstddef>

namespace pyramid {

namespace {

constexpr int64_t kShadowLimit = int64_t{1} << 30;

int32_t clampShadow(int64_t v) { return static_cast<int32_t>(std::clamp(v, -kShadowLimit, kShadowLimit)); }

} // namespace

ShadowParent shadowParentOf(const ResidualHeader& header, int level, int tx, int ty) {
    ShadowParent p;
    p.level = level - 1;
    if (level > header.minLevel) {
        const int n = header.tileSize;
        p.tx = tx / 2;
        p.ty = ty / 2;
        p.px = quadrantOffset(tx, n);
        p.py = quadrantOffset(ty, n);
    }
    return p;
}

// The integer form of the interpolating filter of doc/format.md section 3: the same taps
// (-1, 9, 9, -1) / 16, separable, each sum rounded once with floor((sum + half) / total).
std::vector<int32_t> upsampleShadow(std::span<const int32_t> parent, int parentSize, int size, int px, int py) {
    std::vector<int32_t> out(static_cast<size_t>(size) * static_cast<size_t>(size));
    const auto p = [&](int x, int y) {
        return static_cast<int64_t>(parent[static_cast<size_t>(y) * static_cast<size_t>(parentSize) + static_cast<size_t>(x)]);
    };
    constexpr int64_t w[4] = {-1, 9, 9, -1};
    for (int j = 0; j < size; ++j) {
        const int y = j / 2 + py;
        for (int i = 0; i < size; ++i) {
            const int x = i / 2 + px;
            int64_t u = 0;
            if ((i & 1) == 0 && (j & 1) == 0) {
                u = p(x, y);
            } else if ((j & 1) == 0) {
                u = (9 * (p(x, y) + p(x + 1, y)) - (p(x - 1, y) + p(x + 2, y)) + 8) >> 4;
            } else if ((i & 1) == 0) {
                u = (9 * (p(x, y) + p(x, y + 1)) - (p(x, y - 1) + p(x, y + 2)) + 8) >> 4;
            } else {
                int64_t sum = 0;
                for (int dj = -1; dj <= 2; ++dj) {
                    for (int di = -1; di <= 2; ++di) {
                        sum += w[dj + 1] * w[di + 1] * p(x + di, y + dj);
                    }
                }
                u = (sum + 128) >> 8;
            }
            out[static_cast<size_t>(j) * static_cast<size_t>(size) + static_cast<size_t>(i)] = clampShadow(u);
        }
    }
    return out;
}

std::vector<int32_t> shadowOf(std::span<const int32_t> parentPlane, std::span<const int16_t> residuals) {
    std::vector<int32_t> out(residuals.size());
    for (size_t k = 0; k < out.size(); ++k) {
        out[k] = clampShadow(int64_t{parentPlane.empty() ? 0 : parentPlane[k]} + residuals[k]);
    }
    return out;
}

} // namespace pyramid
