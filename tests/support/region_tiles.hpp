// The one check that a region file (doc/format.md 1.4) holds its subtree of a whole pyramid:
// for residual and ortho files alike.
#pragma once
#include <gtest/gtest.h>

#include <string>

#include "formats/pyramid_set.hpp"

namespace pyramid::test {

// Every tile of `region` (a reader of the region file rooted at `root`, named `name` in messages)
// is `whole`'s tile at its absolute coordinates, byte for byte, down to its own maxLevel.
template <class Reader>
void expectRegionTilesOfWhole(const Reader& region, const Reader& whole, const RegionRoot& root, const std::string& name) {
    for (int d = 0; d <= region.header().maxLevel; ++d) {
        const int side = 1 << d;
        for (int y = 0; y < side; ++y) {
            for (int x = 0; x < side; ++x) {
                const int l = root.level + d, tx = (root.tx << d) + x, ty = (root.ty << d) + y;
                ASSERT_EQ(region.readTileBytes(d, x, y), whole.readTileBytes(l, tx, ty))
                    << name << ": tile " << l << "," << tx << "," << ty;
            }
        }
    }
}

} // namespace pyramid::test
