// The density of the encoder's in-memory grid of levels 0..C for a source of several
// resolutions (encode/residual/residual_reach.hpp, blockLevels): every sample a reached tile of
// levels 0..C reads is sampled, and a coarse base alone is sampled on its own level's vertices
// only, not at level C's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "libpyramid/encode/residual/residual_reach.hpp"

namespace pyramid {
namespace {

// A base everywhere, which has heights of levels 0..3, and a small inset with heights of every
// level, at finest samples [x0, x1] x [y0, y1].
class BaseAndInset final : public HeightSource {
public:
    BaseAndInset(int baseLevel, int64_t x0, int64_t y0, int64_t x1, int64_t y1)
        : baseLevel_(baseLevel), x0_(x0), y0_(y0), x1_(x1), y1_(y1) {}
    void sample(SourceGrid& grid) const override {
        grid.height.assign(static_cast<size_t>(grid.nx * grid.ny), 1.0f);
        grid.valid.assign(static_cast<size_t>(grid.nx * grid.ny), 1);
    }
    bool mayHaveHeights(int64_t, int64_t, int64_t, int64_t) const override { return true; }
    bool mayHaveHeightsAt(int level, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const override {
        return level <= baseLevel_ || (x0 <= x1_ && x0_ <= x1 && y0 <= y1_ && y0_ <= y1);
    }
    bool severalLevels() const override { return true; }

private:
    int baseLevel_;
    int64_t x0_, y0_, x1_, y1_;
};

TEST(BlockLevels, EveryReachedTilesSamplesAndNoMoreWhereTheBaseIsAlone) {
    ResidualPlan plan;
    plan.M = 12;
    plan.minLevel = 3;
    plan.T = 32;
    plan.R = 4;
    plan.N = int64_t{4} << 12; // 16384 finest intervals
    plan.C = 8;
    SourceGrid grid;
    grid.stride = int64_t{1} << (plan.M - plan.C);
    grid.nx = grid.ny = plan.N / grid.stride + 1; // 1025 samples a side: 17 blocks
    const BaseAndInset heights(3, 9000, 5000, 9300, 5400);
    const std::vector<uint8_t> levels = blockLevels(plan, grid, heights, false, 2);
    const int64_t across = (grid.nx + kReachBlock - 1) / kReachBlock;
    ASSERT_EQ(levels.size(), static_cast<size_t>(across * across));
    // Every tile of levels minLevel..C that the heights reach reads samples of blocks of at least
    // its level; the root's levels read every block.
    for (int l = plan.minLevel; l <= plan.C; ++l) {
        for (int ty = 0; ty < plan.tilesPerSide(l); ++ty) {
            for (int tx = 0; tx < plan.tilesPerSide(l); ++tx) {
                if (!tileReached(plan, heights, l, tx, ty)) {
                    continue;
                }
                const SampleBox f = footprintBox(plan, l, tx, ty);
                for (int64_t by = f.y0 / grid.stride / kReachBlock; by <= (f.y1 - 1) / grid.stride / kReachBlock; ++by) {
                    for (int64_t bx = f.x0 / grid.stride / kReachBlock; bx <= (f.x1 - 1) / grid.stride / kReachBlock; ++bx) {
                        ASSERT_GE(levels[static_cast<size_t>(by * across + bx)], 1 + l)
                            << "tile (" << l << "," << tx << "," << ty << "), block " << bx << "," << by;
                    }
                }
            }
        }
    }
    // Far from the inset, a level of the base's or a little deeper (boxes of 8 x 8 blocks of a
    // coarse level take it whole); next to it, C.
    EXPECT_LE(levels[0], 1 + 4);
    EXPECT_LE(levels[static_cast<size_t>(16 * across + 16)], 1 + 4);
    const int64_t ix = 9100 / grid.stride / kReachBlock, iy = 5200 / grid.stride / kReachBlock;
    EXPECT_EQ(levels[static_cast<size_t>(iy * across + ix)], 1 + plan.C);
    // Level-4 tiles span half the plane, level-5 a quarter: the samples stored, a block of level
    // l holding (64 / 2^(C - l))^2, are a small part of every block at level C.
    int64_t samples = 0;
    for (const uint8_t l : levels) {
        const int64_t side = kReachBlock >> (plan.C - (l - 1));
        samples += side * side;
    }
    EXPECT_LT(samples * 8, static_cast<int64_t>(levels.size()) * kReachBlock * kReachBlock) << samples;
    // A source of one resolution, or every block asked for: level C wherever it may have heights.
    for (const uint8_t l : blockLevels(plan, grid, heights, true, 2)) {
        EXPECT_EQ(l, 1 + plan.C);
    }
}

} // namespace
} // namespace pyramid
