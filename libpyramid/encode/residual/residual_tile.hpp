// The residual tile coder of the residual pyramid encoder: one tile's residuals against its
// parent's reconstruction, its TIFF blob, its reconstruction and its error statistics
// (doc/dem-encoding.md, "Residuals"), computed with the runtime's own arithmetic
// (filters/elevation_upsample.hpp), so that the producers rebuild exactly what it measured.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "formats/residual_codec.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/residual/height_source.hpp"

namespace pyramid {

// A folded pyramid's root tile reaches 2 level-0 intervals beyond every edge (its borders of 2
// samples), and so do the root grids given to it (root_fill.hpp).
inline constexpr int64_t kFoldedRootBorder = 2;

// The shape of a residual pyramid as the encoder walks it.
struct ResidualPlan {
    ResidualHeader header;
    int M = 0;         // maxLevel
    int minLevel = 0;
    int T = 0;         // tileSize
    int R = 0;         // root tile intervals
    int64_t N = 0;     // finest intervals
    int C = 0;         // deepest level encoded from the in-memory grid
    float scale = 1.0f;
    bool folded = false;                 // GridEdges::Folded: borders are real samples, never clamped
    ResidualTileCoding coding;           // how tiles are stored (formats/residual_codec.hpp)

    int64_t levelIntervals(int l) const { return static_cast<int64_t>(R) << l; }
    // Level-0 intervals the root tile's grid reaches beyond [0, R] on every side: its borders,
    // real samples where edges are folded (kFoldedRootBorder), clamped copies otherwise (0).
    int64_t rootBorder() const { return folded ? kFoldedRootBorder : 0; }
    int tileIntervals(int l) const { return l < minLevel ? T >> (minLevel - l) : T; }
    int tilesPerSide(int l) const { return l < minLevel ? 1 : 1 << (l - minLevel); }
};

// Per-level error statistics, merged in a fixed order (sums of squares are order-sensitive).
struct LevelStats {
    int64_t samples = 0;
    double maxError = 0.0;
    double sumSquares = 0.0;
    int maxAbsResidual = 0;
    int64_t overflowResidual = 0; // largest |r| beyond int16, 0 if none

    void merge(const LevelStats& o) {
        samples += o.samples;
        maxError = std::max(maxError, o.maxError);
        sumSquares += o.sumSquares;
        maxAbsResidual = std::max(maxAbsResidual, o.maxAbsResidual);
        overflowResidual = std::max(overflowResidual, o.overflowResidual);
    }
};

// A tile encoded: its blob, its statistics, and its reconstruction ((n + 5)^2 float32, row 0
// = bottom), which its children are predicted from.
struct EncodedTile {
    int level = 0, tx = 0, ty = 0;
    // The whole subtree rooted here is residual 0, given as this one item (a sparse output's log
    // takes it so; blob and recon are empty).
    bool emptySubtree = false;
    // Neither stored nor encoded: under an empty subtree given above it.
    bool skipped = false;
    std::vector<float> recon;
    std::vector<uint8_t> blob;
    LevelStats stats;
};

// Encodes tile (l, tx, ty) against its parent's reconstruction (null at the root), reading the
// source heights of level-l positions from `src` (finest-grid coordinates; clamped to the map
// unless the plan's edges are folded).
EncodedTile encodeResidualTile(const ResidualPlan& plan, int l, int tx, int ty, const std::vector<float>* parent,
                               const SourceGrid& src);

// The blob encodeResidualTile writes for a tile of `size` samples a side whose residuals are all
// 0 (a tile without valid samples: its heights are its parent's prediction).
std::vector<uint8_t> zeroResidualBlob(int size, const ResidualTileCoding& coding);

} // namespace pyramid
