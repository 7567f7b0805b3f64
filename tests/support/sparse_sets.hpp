// The one check that a sparse residual set (formats/sparse_set.hpp) is the pyramid a dense build
// writes: every tile of the dense file is the set's, residual for residual, where a file of the
// set holds it, and all residual 0 where none does.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"

namespace pyramid::test {

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
