#include "libpyramid/encode/residual/residual_reach.hpp"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <limits>

#include "libpyramid/encode/residual/root_fill.hpp"
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
        const int64_t mx = bx1 - bx0 > 1 ? (bx0 + bx1) / 2 : bx1, my = by1 - by0 > 1 ? (by0 + by1) / 2 : by1;
        mark(bx0, by0, mx, my);
        if (mx < bx1) {
            mark(mx, by0, bx1, my);
        }
        if (my < by1) {
            mark(bx0, my, mx, by1);
            if (mx < bx1) {
                mark(mx, my, bx1, by1);
            }
        }
    };
    constexpr int64_t kBox = 8;
    const int64_t boxesAcross = (across + kBox - 1) / kBox, boxesDown = (down + kBox - 1) / kBox;
    parallelFor(boxesAcross * boxesDown, threads, [&](int64_t b) {
        const int64_t bx = (b % boxesAcross) * kBox, by = (b / boxesAcross) * kBox;
        mark(bx, by, std::min(across, bx + kBox), std::min(down, by + kBox));
    });
    return reachable;
}

void allocateReachableRows(SourceGrid& grid, const std::vector<uint8_t>& reachable, int64_t keep) {
    const int64_t across = (grid.nx + kReachBlock - 1) / kReachBlock;
    std::vector<size_t> rows(static_cast<size_t>(grid.ny));
    const auto width = static_cast<size_t>(grid.nx);
    size_t stored = 0;
    for (int64_t row = 0; row < grid.ny; ++row) {
        const uint8_t* blocks = reachable.data() + (row / kReachBlock) * across;
        const bool kept =
            (keep > 0 && row % keep == 0) || std::find(blocks, blocks + across, uint8_t{1}) != blocks + across;
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
    const std::vector<uint8_t> reachable =
        reachableBlocks(grid, *job.heights, static_cast<bool>(options.reconstruction), threads);
    // The root's rows (every 2^C-th) are stored whatever they reach: their nodata is filled.
    allocateReachableRows(grid, reachable, int64_t{1} << plan.C);
    parallelFor(grid.ny, threads, [&](int64_t row) {
        const uint8_t* blocks = reachable.data() + (row / kReachBlock) * blocksAcross;
        for (int64_t b0 = 0; b0 < blocksAcross;) {
            int64_t b1 = b0;
            while (b1 < blocksAcross && blocks[b1] == blocks[b0]) {
                ++b1;
            }
            const int64_t c0 = b0 * kReachBlock, c1 = std::min(grid.nx, b1 * kReachBlock);
            if (blocks[b0]) {
                SourceGrid line;
                line.stride = grid.stride;
                line.x0 = grid.x0 + c0 * grid.stride;
                line.y0 = grid.y0 + row * grid.stride;
                line.nx = c1 - c0;
                line.ny = 1;
                job.heights->sample(line);
                const auto at = static_cast<std::ptrdiff_t>(grid.rowStart(line.y0) + static_cast<size_t>(c0));
                std::copy(line.height.begin(), line.height.end(), grid.height.begin() + at);
                std::copy(line.valid.begin(), line.valid.end(), grid.valid.begin() + at);
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
