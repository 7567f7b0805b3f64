// Sparse residual sets (formats/sparse_set.hpp) in tests: a height source on a patch of the finest
// grid, and the one check that a sparse set is the pyramid a dense build writes: every tile of
// the dense file is the set's, residual for residual, where a file of the set holds it, and all
// residual 0 where none does.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/residual/height_source.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"

namespace pyramid::test {

// Heights on a rectangle of finest positions, nodata elsewhere; with `exact`, it tells the
// encoder where heights can be, so that the encoder skips the rest (rows of its grid and of its
// footprints not stored, subtrees not sampled, level-C reconstructions not kept).
class Patch final : public HeightSource {
public:
    Patch(int64_t x0, int64_t y0, int64_t x1, int64_t y1, bool exact) : x0_(x0), y0_(y0), x1_(x1), y1_(y1), exact_(exact) {}
    void sample(SourceGrid& g) const override {
        g.height.assign(static_cast<size_t>(g.nx * g.ny), 0.0f);
        g.valid.assign(g.height.size(), 0);
        for (int64_t j = 0; j < g.ny; ++j) {
            for (int64_t i = 0; i < g.nx; ++i) {
                const int64_t x = g.x0 + i * g.stride, y = g.y0 + j * g.stride;
                if (x >= x0_ && x <= x1_ && y >= y0_ && y <= y1_) {
                    const size_t k = static_cast<size_t>(i + j * g.nx);
                    g.height[k] = 100.0f + 0.37f * static_cast<float>(x) - 0.21f * static_cast<float>(y) +
                                  ((x * y) % 7 == 0 ? 25.0f : 0.0f);
                    g.valid[k] = 1;
                }
            }
        }
    }
    bool mayHaveHeights(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const override {
        return !exact_ || (x1 >= x0_ && x0 <= x1_ && y1 >= y0_ && y0 <= y1_);
    }

private:
    int64_t x0_, y0_, x1_, y1_;
    bool exact_;
};

// Returns the tiles no file of the set holds (all residual 0 in the dense file).
inline int64_t expectSparseSetOfDense(const std::string& dense, const std::string& sparse) {
    const auto whole = ResidualFileReader::open(dense);
    const PyramidSet set = openPyramidSet(sparse);
    EXPECT_TRUE(pyramidSetProblems(set).empty()) << sparse;
    const ResidualHeader& h = whole->header();
    int64_t beyond = 0;
    for (int l = 0; l <= h.maxLevel; ++l) {
        const int side = static_cast<int>(h.tilesPerSide(l));
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                const std::vector<int16_t> r = whole->readTile(l, tx, ty);
                if (!residualSetHolds(set, l, tx, ty)) {
                    ++beyond;
                    EXPECT_TRUE(std::all_of(r.begin(), r.end(), [](int16_t v) { return v == 0; }))
                        << sparse << ": tile " << l << "," << tx << "," << ty << " has residuals but no file";
                    continue;
                }
                EXPECT_EQ(storedResidualTile(set, l, tx, ty).residuals, r)
                    << sparse << ": tile " << l << "," << tx << "," << ty;
            }
        }
    }
    return beyond;
}

} // namespace pyramid::test
