// The root level's missing heights, filled before the residual pyramid is encoded, so that
// every tile has a prediction to start from (doc/dem-encoding.md, "Nodata").
#pragma once
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "libpyramid/encode/residual/height_source.hpp"
#include "libpyramid/encode/residual/residual_tile.hpp"

namespace pyramid {

// The sum and count of the valid heights at positions (i x stride, j x stride) of [0, N]^2:
// blocks of 256 x 256 of them, those no valid height can reach (mayHaveHeights) skipped, one
// row of blocks at a time on `threads`, summed in block order whatever the threads.
std::pair<double, int64_t> sumValidHeights(const HeightSource& heights, int64_t N, int64_t stride, int threads);

// Root values solved for outside the pyramid (a planet's six faces as one surface,
// encode/dem/sphere_root_fill.hpp): for each position of the root grid (side x side with side =
// R + 1 + 2 x ResidualPlan::rootBorder(), south row first, borders included), the height a nodata sample there takes,
// or NaN where the pyramid solves it itself (Gauss-Seidel sweeps with every other position fixed,
// from `start`).
struct GivenRootFill {
    std::vector<double> value;
    double start = 0.0;
};

// Root-level nodata: with `given` (asked for only when the root has nodata), its values, and
// sweeps only for the positions it leaves NaN. Without: a fixed number of Gauss-Seidel sweeps of
// Laplace's equation over the level-0 positions (with folded edges, its border positions too),
// from the mean of the valid ones (or of every valid grid sample when the root has none; or,
// when the grid has none either, of every valid finest sample, read from `heights` block by
// block on `threads`). Filled samples get valid = 2: encoded, but not counted as source. Throws
// Error naming `input` when, without `given`, no finest sample is valid.
void fillRootNodata(const ResidualPlan& plan, SourceGrid& grid, const HeightSource& heights, int threads,
                    const std::function<const GivenRootFill&()>& given, const std::string& input);

} // namespace pyramid
