#include "libpyramid/encode/ortho/ortho_levels_impl.hpp"

#include <algorithm>

#include "libpyramid/support/box_quarters.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

// The blocks of level c whole (a face's margin included) whose finest pixels the input may
// reach, those a SparseLevel of it stores: every block unless the average of 0s is 0. Found by
// halving the level's blocks as long as a part is not known blank, so that a face a small map
// barely touches asks its pixel source a few hundred times, not once per block.
BlockMask OrthoLevels::Impl::reachOf(int c) const {
    if (several) {
        return severalMask(c);
    }
    const int k = M - c;
    const int64_t mc = margin(c);
    const int64_t side = sideWithMargin(c);
    const int64_t across = BlockMask::blocks(side);
    BlockMask stored(side, blankStaysBlank ? 0 : 1);
    if (blankStaysBlank) {
        const auto mark = [&](const auto& self, int64_t bx0, int64_t by0, int64_t bx1, int64_t by1) -> void {
            const int64_t x0 = bx0 * kSparseBlock, y0 = by0 * kSparseBlock;
            const int64_t x1 = std::min(side, bx1 * kSparseBlock), y1 = std::min(side, by1 * kSparseBlock);
            if (pixels->knownBlank((x0 - mc) << k, (y0 - mc) << k, (x1 - x0) << k, (y1 - y0) << k)) {
                return;
            }
            if (bx1 - bx0 == 1 && by1 - by0 == 1) {
                stored.store(bx0, by0);
                return;
            }
            forEachQuarter(bx0, by0, bx1, by1,
                           [&](int64_t a0, int64_t b0, int64_t a1, int64_t b1) { self(self, a0, b0, a1, b1); });
        };
        mark(mark, 0, 0, across, across);
        stored.seal();
    }
    return stored;
}

// Row `row` of level c between columns [x0, x1) (the level's pixels, a face's margin from 0),
// each pixel the reduction of its 2^(M-c) x 2^(M-c) finest block, written into `level`: only
// its stored blocks are sampled, in runs of neighbouring ones.
void OrthoLevels::Impl::bandInto(SparseLevel& level, int c, int64_t row, int64_t x0, int64_t x1) const {
    const int k = M - c;
    const int64_t mc = margin(c);
    level.mask().forEachRun(row / kSparseBlock, x0 / kSparseBlock, (x1 + kSparseBlock - 1) / kSparseBlock,
                            [&](int64_t first, int64_t end) {
                                const int64_t from = std::max(x0, first * kSparseBlock);
                                const int64_t to = std::min(x1, end * kSparseBlock);
                                if (from < to) {
                                    level.write(reducedFinest((from - mc) << k, (row - mc) << k,
                                                              static_cast<int>((to - from) << k), 1 << k, k),
                                                from, row);
                                }
                            });
}

// Levels 0..C, from bands of 2^(M-C) finest rows, a face's margin included; northern rows
// first, so that an input still being decoded from its first row (PNG) is worked on as it
// arrives.
std::vector<SparseLevel> OrthoLevels::Impl::coarseLevelsFromBands(int c, const BlockMask& reach) const {
    if (several) {
        return severalCoarseLevels(c);
    }
    std::vector<SparseLevel> levels(static_cast<size_t>(c) + 1);
    SparseLevel& levelC = levels[static_cast<size_t>(c)];
    levelC = SparseLevel(sideWithMargin(c), channels, reach);
    const int64_t sideC = levelC.side();
    const std::vector<int64_t> rows = storedRowsFromTop(levelC);
    parallelFor(static_cast<int64_t>(rows.size()), threads,
                [&](int64_t i) { bandInto(levelC, c, rows[static_cast<size_t>(i)], 0, sideC); });
    reduceCoarserLevels(levels);
    return levels;
}

void OrthoLevels::Impl::reduceCoarserLevels(std::vector<SparseLevel>& levels) const {
    for (int l = static_cast<int>(levels.size()) - 2; l >= 0; --l) {
        levels[static_cast<size_t>(l)] = levels[static_cast<size_t>(l) + 1].reduced(averager, threads);
    }
}

// The level-c pixels beyond the map's edge (PixelSource::margin: a face's 2 << c pixels on each
// side), each the reduction of its 2^k x 2^k finest block as in coarseLevelsFromBands: the rows
// wholly in the margin from bands across the whole width, the other rows' margin columns from
// bands as wide as the margin. The pixels over the map itself come from the subtrees.
void OrthoLevels::Impl::marginFromBands(int c, SparseLevel& levelC) const {
    const int64_t mc = margin(c);
    const int64_t inner = levelWidth(c);
    const int64_t sideC = inner + 2 * mc;
    const std::vector<int64_t> rows = storedRowsFromTop(levelC);
    parallelFor(static_cast<int64_t>(rows.size()), threads, [&](int64_t i) {
        const int64_t row = rows[static_cast<size_t>(i)];
        if (row < mc || row >= sideC - mc) {
            bandInto(levelC, c, row, 0, sideC);
        } else {
            bandInto(levelC, c, row, 0, mc);
            bandInto(levelC, c, row, mc + inner, sideC);
        }
    });
}

} // namespace pyramid
