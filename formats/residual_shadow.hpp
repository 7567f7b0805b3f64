// The integer heights of a residual file that version 3 of the context-coded tile predicts from
// (doc/format.md 1.8, "Parent mode"): each tile's *shadow*, its residuals added to its parent's
// shadow upsampled in integers. A property of the file's residuals alone, computed the same way
// by the writer and by every reader, whatever codec each tile is stored in; close to the heights
// in residual units, but neither the heights of section 3 nor any runtime's.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "formats/residual_file.hpp"

namespace pyramid {

// Where a tile's parent is and which of its samples the tile's grid starts at (doc/format.md 1.3):
// the tile of the level above (its quadrant (tx % 2, ty % 2) below level minLevel + 1, the whole
// tile otherwise). Level 0 has none: its parent plane is 0.
struct ShadowParent {
    int level = 0, tx = 0, ty = 0;
    int px = 1, py = 1; // the parent sample under the child's sample (0, 0) is (px + 0 / 2, py + 0 / 2)
};
ShadowParent shadowParentOf(const ResidualHeader& header, int level, int tx, int ty);

// The parent plane of a tile of `size` samples a side: the parent's shadow (`parentSize` a
// side) upsampled in integers from (px, py) on.
std::vector<int32_t> upsampleShadow(std::span<const int32_t> parent, int parentSize, int size, int px, int py);

// A tile's shadow: its parent plane plus its residuals, clamped to +-2^30.
std::vector<int32_t> shadowOf(std::span<const int32_t> parentPlane, std::span<const int16_t> residuals);

} // namespace pyramid
