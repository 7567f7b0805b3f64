// Residual tiles the codec tests share, their check of a refused blob, and a walk over a file's tiles.
#pragma once
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_file.hpp"

namespace pyramid::test {

// size x size residuals drawn uniformly from [-spread, spread].
inline std::vector<int16_t> residualNoise(int size, int spread, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> d(-spread, spread);
    std::vector<int16_t> v(static_cast<size_t>(size) * static_cast<size_t>(size));
    for (int16_t& x : v) {
        x = static_cast<int16_t>(d(rng));
    }
    return v;
}

// Decoding `blob` as a context-coded tile of `size` samples named `where` fails with one
// line that starts with `where` and mentions `mention`.
inline void expectContextBlobRefused(const std::vector<uint8_t>& blob, int size, const std::string& where,
                                     const std::string& mention) {
    try {
        decodeContextResiduals(blob, size, where);
        ADD_FAILURE() << "accepted: " << mention;
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(where + ": ", 0), 0u) << what;
        EXPECT_NE(what.find(mention), std::string::npos) << what;
    }
}

// f(level, tx, ty) for every tile of a file.
template <class F>
void forEachTile(const ResidualHeader& h, F f) {
    for (int l = 0; l <= h.maxLevel; ++l) {
        for (int ty = 0; ty < h.tilesPerSide(l); ++ty) {
            for (int tx = 0; tx < h.tilesPerSide(l); ++tx) {
                f(l, tx, ty);
            }
        }
    }
}

} // namespace pyramid::test
