#include "libpyramid/encode/residual/residual_reach.hpp"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <limits>

#include "libpyramid/encode/residual/root_fill.hpp"
#include "libpyramid/support/box_quarters.hpp"
#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

SampleBox footprintBox(const ResidualPlan& plan, int l, int tx, int ty) {
    const int64_t T = plan.T;
    const int64_t unit = int64_t{1} << (plan.M - l);
    const int64_t lo = plan.folded ? std::numeric_limits<int64_t>::min() : 0;
    const int64_t hi = plan.folded ? std::numeric_limits<int64_t>::max() : plan.N;
    return SampleBox{std::max<int64_t>(lo, (static_cast<int64_t>(tx) * T - 2) * unit),
                     std::max<int64_t>(lo, (static_cast<int64_t>(ty) * T - 2) * unit),
                     std::min<int64_t>(hi, (static_cast<int64_t>(tx) * T + T + 2) * unit) + 1,
                     std::min<int64_t>(hi, (static_cast<int64_t>(ty) * T + T + 2) * unit) + 1};
}

bool tileReached(const ResidualPlan& plan, const HeightSource& heights, int l, int tx, int ty) {
    const SampleBox f = footprintBox(plan, l, tx, ty);
    return heights.mayHaveHeightsAt(l, f.x0, f.y0, f.x1 - 1, f.y1 - 1);
}

std::vector<uint8_t> reachableBlocks(const SourceGrid& grid, const HeightSource& heights, bool everywhere, int threads) {
    const int64_t across = (grid.nx + kReachBlock - 1) / kReachBlock;
    const int64_t down = (grid.ny + kReachBlock - 1) / kReachBlock;
    std::vector<uint8_t> reachable(static_cast<size_t>(across * down), 1);
    if (everywhere) {
        return reachable;
    }
    // Asked of boxes of blocks, halved where they may have heights: a box no valid height can
    // reach leaves every block in it 0 without asking for each (mayHaveHeights claims nothing it
    // cannot; a block's own answer decides it). Rows of boxes of 8 x 8 blocks go to the threads.
    const auto mayHave = [&](int64_t bx0, int64_t by0, int64_t bx1, int64_t by1) { // blocks [bx0, bx1) x [by0, by1)
        const int64_t x0 = grid.x0 + bx0 * kReachBlock * grid.stride, y0 = grid.y0 + by0 * kReachBlock * grid.stride;
        const int64_t x1 = grid.x0 + std::min(grid.nx - 1, bx1 * kReachBlock - 1) * grid.stride;
        const int64_t y1 = grid.y0 + std::min(grid.ny - 1, by1 * kReachBlock - 1) * grid.stride;
        return heights.mayHaveHeights(x0, y0, x1, y1);
    };
    const std::function<void(int64_t, int64_t, int64_t, int64_t)> mark = [&](int64_t bx0, int64_t by0, int64_t bx1,
                                                                              int64_t by1) {
        const bool may = mayHave(bx0, by0, bx1, by1);
        if (!may || (bx1 - bx0 == 1 && by1 - by0 == 1)) {
            for (int64_t by = by0; by < by1; ++by) {
                std::fill_n(reachable.begin() + static_cast<std::ptrdiff_t>(by * across + bx0), bx1 - bx0,
                            static_cast<uint8_t>(may ? 1 : 0));
            }
            return;
        }
        forEachQuarter(bx0, by0, bx1, by1, mark);
    };
    constexpr int64_t kBox = 8;
    const int64_t boxesAcross = (across + kBox - 1) / kBox, boxesDown = (down + kBox - 1) / kBox;
    parallelFor(boxesAcross * boxesDown, threads, [&](int64_t b) {
        const int64_t bx = (b % boxesAcross) * kBox, by = (b / boxesAcross) * kBox;
        mark(bx, by, std::min(across, bx + kBox), std::min(down, by + kBox));
    });
    return reachable;
}

std::vector<uint8_t> blockLevels(const ResidualPlan& plan, const SourceGrid& grid, const HeightSource& heights,
                                 bool everywhere, int threads) {
    const int top = plan.C, floor = std::min(plan.C, std::max(0, plan.minLevel - 1));
    if (everywhere || !heights.severalLevels()) {
        std::vector<uint8_t> levels = reachableBlocks(grid, heights, everywhere, threads);
        for (uint8_t& l : levels) {
            l = l ? static_cast<uint8_t>(1 + top) : 0;
        }
        return levels;
    }
    const int64_t across = (grid.nx + kReachBlock - 1) / kReachBlock;
    const int64_t down = (grid.ny + kReachBlock - 1) / kReachBlock;
    std::vector<uint8_t> levels(static_cast<size_t>(across * down), 0);
    // The samples of blocks [bx0, bx1) x [by0, by1), widened by `reach` within the grid.
    const auto box = [&](int64_t bx0, int64_t by0, int64_t bx1, int64_t by1, int64_t reach) {
        const int64_t first = grid.x0, last = grid.x0 + (grid.nx - 1) * grid.stride; // the grid is square
        return SampleBox{std::max(first, grid.x0 + bx0 * kReachBlock * grid.stride - reach),
                         std::max(first, grid.y0 + by0 * kReachBlock * grid.stride - reach),
                         std::min(last, grid.x0 + std::min(grid.nx - 1, bx1 * kReachBlock - 1) * grid.stride + reach),
                         std::min(last, grid.y0 + std::min(grid.ny - 1, by1 * kReachBlock - 1) * grid.stride + reach)};
    };
    // Whether the blocks' samples are read by level l: a tile of level l >= minLevel whose
    // footprint meets them is reached (their samples widened by a tile and its borders); the
    // root's levels (below minLevel) read every sample where heights may be.
    const auto readAt = [&](int l, int64_t bx0, int64_t by0, int64_t bx1, int64_t by1) {
        if (l < plan.minLevel) {
            const SampleBox b = box(bx0, by0, bx1, by1, 0);
            return heights.mayHaveHeights(b.x0, b.y0, b.x1, b.y1);
        }
        const SampleBox b = box(bx0, by0, bx1, by1, (static_cast<int64_t>(plan.T) + 4) << (plan.M - l));
        return heights.mayHaveHeightsAt(l, b.x0, b.y0, b.x1, b.y1);
    };
    const auto fill = [&](int64_t bx0, int64_t by0, int64_t bx1, int64_t by1, int l) {
        for (int64_t by = by0; by < by1; ++by) {
            std::fill_n(levels.begin() + static_cast<std::ptrdiff_t>(by * across + bx0), bx1 - bx0,
                        static_cast<uint8_t>(l < floor ? 0 : 1 + l));
        }
    };
    // A box takes the deepest level that reads it, never less than any of its blocks needs.
    // Boxes of levels within 2 of C (a block at least 1/16 as dense as C) are halved down to
    // their blocks; boxes of coarser levels take that level whole (more samples than their
    // blocks may need, far fewer questions). Below the floor, no level reads it: not sampled.
    const int halvedFrom = std::max(floor, top - 2);
    const std::function<void(int64_t, int64_t, int64_t, int64_t, int)> assign = [&](int64_t bx0, int64_t by0,
                                                                                  int64_t bx1, int64_t by1, int hi) {
        while (hi >= floor && !readAt(hi, bx0, by0, bx1, by1)) {
            --hi;
        }
        if (hi < halvedFrom || (bx1 - bx0 == 1 && by1 - by0 == 1)) {
            fill(bx0, by0, bx1, by1, hi);
            return;
        }
        forEachQuarter(bx0, by0, bx1, by1,
                       [&](int64_t x0, int64_t y0, int64_t x1, int64_t y1) { assign(x0, y0, x1, y1, hi); });
    };
    constexpr int64_t kBox = 8;
    const int64_t boxesAcross = (across + kBox - 1) / kBox, boxesDown = (down + kBox - 1) / kBox;
    parallelFor(boxesAcross * boxesDown, threads, [&](int64_t b) {
        const int64_t bx = (b % boxesAcross) * kBox, by = (b / boxesAcross) * kBox;
        assign(bx, by, std::min(across, bx + kBox), std::min(down, by + kBox), top);
    });
    return levels;
}

void allocateReachableRows(SourceGrid& grid, const std::vector<uint8_t>& reachable, int64_t keep) {
    const int64_t across = (grid.nx + kReachBlock - 1) / kReachBlock;
    std::vector<uint8_t> sampled(static_cast<size_t>(grid.ny), 0);
    for (int64_t row = 0; row < grid.ny; ++row) {
        const uint8_t* blocks = reachable.data() + (row / kReachBlock) * across;
        sampled[static_cast<size_t>(row)] = std::find(blocks, blocks + across, uint8_t{1}) != blocks + across;
    }
    allocateRows(grid, sampled, keep);
}

void allocateRows(SourceGrid& grid, const std::vector<uint8_t>& sampled, int64_t keep) {
    std::vector<size_t> rows(static_cast<size_t>(grid.ny));
    const auto width = static_cast<size_t>(grid.nx);
    size_t stored = 0;
    for (int64_t row = 0; row < grid.ny; ++row) {
        const bool kept = (keep > 0 && row % keep == 0) || sampled[static_cast<size_t>(row)] != 0;
        rows[static_cast<size_t>(row)] = kept ? stored++ * width : SIZE_MAX;
    }
    grid.rows.clear();
    if (stored < rows.size()) {
        for (size_t& r : rows) {
            r = r == SIZE_MAX ? stored * width : r;
        }
        grid.rows = std::move(rows);
        ++stored;
    }
    grid.height.assign(stored * width, 0.0f);
    grid.valid.assign(stored * width, 0);
}

SourceGrid sampleLevelGrid(const ResidualPlan& plan, const ResidualPyramidJob& job, const ResidualEncodeOptions& options,
                           int threads) {
    SourceGrid grid;
    // One level-C row of samples at a time (each reads two input rows at most), in row order,
    // so the input streams through once.
    // With folded edges the grid reaches the root tile's borders, 2 level-0 intervals beyond.
    grid.stride = int64_t{1} << (plan.M - plan.C);
    const int64_t margin = plan.rootBorder() << plan.M;
    grid.x0 = grid.y0 = -margin;
    grid.nx = grid.ny = (plan.N + 2 * margin) / grid.stride + 1;
    // Blocks of kReachBlock x kReachBlock grid samples that no valid height can reach are left nodata
    // without sampling (what sampling them gives); each row samples its other runs of blocks.
    // With the reconstruction hook every block is sampled and every row stored: the encoding
    // without any skip, which the skips must give byte for byte.
    const int64_t blocksAcross = (grid.nx + kReachBlock - 1) / kReachBlock;
    // Each block sampled on the vertices of the deepest level whose tiles read it (a coarse base
    // beside a fine inset: its own level's, every 2^(C - l)-th sample), the others left nodata.
    const std::vector<uint8_t> levels =
        blockLevels(plan, grid, *job.heights, static_cast<bool>(options.reconstruction), threads);
    const auto step = [&](uint8_t level) { return int64_t{1} << (plan.C - (level - 1)); };
    // The rows a block samples, and the root's (every 2^C-th: their nodata is filled), are stored.
    std::vector<uint8_t> rowSampled(static_cast<size_t>(grid.ny), 0);
    for (int64_t row = 0; row < grid.ny; ++row) {
        const uint8_t* blocks = levels.data() + (row / kReachBlock) * blocksAcross;
        for (int64_t b = 0; b < blocksAcross && !rowSampled[static_cast<size_t>(row)]; ++b) {
            rowSampled[static_cast<size_t>(row)] = blocks[b] != 0 && row % step(blocks[b]) == 0;
        }
    }
    allocateRows(grid, rowSampled, int64_t{1} << plan.C);
    parallelFor(grid.ny, threads, [&](int64_t row) {
        const uint8_t* blocks = levels.data() + (row / kReachBlock) * blocksAcross;
        for (int64_t b0 = 0; b0 < blocksAcross;) {
            int64_t b1 = b0;
            while (b1 < blocksAcross && blocks[b1] == blocks[b0]) {
                ++b1;
            }
            const int64_t every = blocks[b0] ? step(blocks[b0]) : 0;
            // Columns that are multiples of `every` in [c0, c1).
            const int64_t c0 = every > 0 ? (b0 * kReachBlock + every - 1) / every * every : 0;
            const int64_t c1 = std::min(grid.nx, b1 * kReachBlock);
            if (every > 0 && row % every == 0 && c0 < c1) {
                SourceGrid line;
                line.stride = grid.stride * every;
                line.x0 = grid.x0 + c0 * grid.stride;
                line.y0 = grid.y0 + row * grid.stride;
                line.nx = (c1 - 1 - c0) / every + 1;
                line.ny = 1;
                job.heights->sample(line);
                const size_t at = grid.rowStart(line.y0) + static_cast<size_t>(c0);
                for (int64_t k = 0; k < line.nx; ++k) {
                    grid.height[at + static_cast<size_t>(k * every)] = line.height[static_cast<size_t>(k)];
                    grid.valid[at + static_cast<size_t>(k * every)] = line.valid[static_cast<size_t>(k)];
                }
            }
            b0 = b1;
        }
    });
    fillRootNodata(plan, grid, *job.heights, threads, job.rootFill, job.input);
    return grid;
}

bool reachesEverywhere(const ResidualPlan& plan, const HeightSource& heights, int threads) {
    const int level = std::max(std::min(plan.C + 1, plan.M), plan.minLevel);
    const int64_t side = plan.tilesPerSide(level);
    std::atomic<bool> everywhere{true};
    parallelFor(side * side, threads, [&](int64_t m) {
        if (everywhere.load(std::memory_order_relaxed)) {
            const auto [tx, ty] = mortonDecode(static_cast<uint64_t>(m));
            if (!tileReached(plan, heights, level, static_cast<int>(tx), static_cast<int>(ty))) {
                everywhere.store(false, std::memory_order_relaxed);
            }
        }
    });
    return everywhere.load();
}

} // namespace pyramid
