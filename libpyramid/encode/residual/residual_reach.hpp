// Where valid heights can be, for the residual encoder (doc/dem-encoding.md, "Order of work and
// memory bounds", "Sparse outputs"): the finest samples a tile or subtree is encoded from, which
// tiles and blocks of samples a HeightSource's heights may reach (at a level: mayHaveHeightsAt),
// and the in-memory grid of levels 0..C, sampled and stored only where they do.
#pragma once
#include <cstdint>
#include <vector>

#include "libpyramid/encode/residual/height_source.hpp"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"
#include "libpyramid/encode/residual/residual_tile.hpp"

namespace pyramid {

// A half-open box of finest samples [x0, x1) x [y0, y1).
struct SampleBox {
    int64_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// The finest samples subtree (l, tx, ty) (l >= minLevel) is encoded from: its root tile with 2
// border samples of level l beyond each edge; clamped to the map unless edges are folded.
SampleBox footprintBox(const ResidualPlan& plan, int l, int tx, int ty);

// Whether heights of level l (HeightSource::mayHaveHeightsAt) may reach tile (l, tx, ty)
// (l >= minLevel) or its borders.
bool tileReached(const ResidualPlan& plan, const HeightSource& heights, int l, int tx, int ty);

// Tiles in a subtree rooted at level l, down to level M.
inline int64_t subtreeTiles(int M, int l) { return ((int64_t{1} << (2 * (M - l + 1))) - 1) / 3; }

// The side, in samples, of the blocks a grid is sampled and stored by where valid heights can be.
inline constexpr int64_t kReachBlock = 64;

// For each block of kReachBlock x kReachBlock samples of `grid` (blocks across, then down: the
// blocks a row of samples crosses are those of its row / kReachBlock-th row of blocks), 1 where
// `heights` may have a valid height, 0 where it has none; 1 everywhere with `everywhere`.
std::vector<uint8_t> reachableBlocks(const SourceGrid& grid, const HeightSource& heights, bool everywhere, int threads);

// For the in-memory grid of levels 0..C (sampleLevelGrid), each block's density: 0 where no
// level reads it (no valid height can reach it), else 1 + the deepest level l (at least
// max(0, minLevel - 1), at most C) whose encoded tiles may read its samples: those of level l >=
// minLevel whose footprint meets the block and which heights of level l may reach (tileReached),
// or the root's. The block's samples on level l's vertices (every 2^(C - l)-th grid sample across
// and down) are all that those tiles read. A source of one resolution (HeightSource::severalLevels
// false), and `everywhere`, give reachableBlocks at C. Found by halving boxes of blocks, a box
// given the deepest level that may read it (never less than any of its blocks needs); only boxes
// of the densest levels are halved down to single blocks.
std::vector<uint8_t> blockLevels(const ResidualPlan& plan, const SourceGrid& grid, const HeightSource& heights,
                                 bool everywhere, int threads);

// Allocates grid's samples, nodata, for the rows that cross a block marked in `reachable`
// (reachableBlocks) and for every `keep`-th row (0: none); the other rows share one row of
// nodata (SourceGrid::rows). When every row is stored they lie one after another, without a
// table.
void allocateReachableRows(SourceGrid& grid, const std::vector<uint8_t>& reachable, int64_t keep);
// The same for the rows marked in `sampled` (one byte a row) and every `keep`-th.
void allocateRows(SourceGrid& grid, const std::vector<uint8_t>& sampled, int64_t keep);

// Pass 1: the in-memory grid of levels 0..C (every 2^(M-C)-th finest sample), its root's nodata
// filled.
SourceGrid sampleLevelGrid(const ResidualPlan& plan, const ResidualPyramidJob& job, const ResidualEncodeOptions& options,
                           int threads);

// Whether valid heights may reach every tile of the level the subtrees start at (level C + 1, or
// M when every level is held in memory): a pyramid they fill, which a sparse output writes as one
// file like a dense one.
bool reachesEverywhere(const ResidualPlan& plan, const HeightSource& heights, int threads);

} // namespace pyramid
