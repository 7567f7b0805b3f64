#include "tests/support/pyramid_tiles.hpp"

#include <algorithm>
#include <random>

namespace pyramid::test {

namespace {

// Every tile of levels [0, maxLevel], shuffled deterministically: writers must accept any order.
template <class TilesPerSide>
std::vector<TileId> shuffledTiles(int maxLevel, TilesPerSide tilesPerSide, unsigned seed) {
    std::vector<TileId> ids;
    for (int level = 0; level <= maxLevel; ++level) {
        const int side = static_cast<int>(tilesPerSide(level));
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                ids.push_back({level, tx, ty});
            }
        }
    }
    std::mt19937 rng(seed);
    std::shuffle(ids.begin(), ids.end(), rng);
    return ids;
}

} // namespace

std::vector<TileId> residualTiles(const ResidualHeader& h, unsigned seed) {
    return shuffledTiles(h.maxLevel, [&](int level) { return h.tilesPerSide(level); }, seed);
}

std::vector<TileId> orthoTiles(const OrthoHeader& h, unsigned seed) {
    return shuffledTiles(h.maxLevel, [](int level) { return int64_t{1} << level; }, seed);
}

std::vector<int16_t> residualsFor(const ResidualHeader& h, const TileId& t) {
    const int n = h.tileSamples(t.level);
    std::vector<int16_t> v(static_cast<size_t>(n) * static_cast<size_t>(n));
    for (size_t k = 0; k < v.size(); ++k) {
        const long x = static_cast<long>(k) * 2654435761L + t.level * 1000 + t.tx * 77 + t.ty * 131;
        v[k] = static_cast<int16_t>(static_cast<uint16_t>(x & 0xffff));
    }
    return v;
}

std::vector<uint8_t> smoothPixels(int size, int channels, const TileId& t) {
    std::vector<uint8_t> v(static_cast<size_t>(size) * size * channels);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            for (int c = 0; c < channels; ++c) {
                const int value = 30 + 3 * x + 2 * y + 25 * c + 7 * t.level + 5 * t.tx + 3 * t.ty;
                v[(static_cast<size_t>(y) * size + x) * channels + c] = static_cast<uint8_t>(std::min(value, 255));
            }
        }
    }
    return v;
}

} // namespace pyramid::test
