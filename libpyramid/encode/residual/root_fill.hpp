// The root level's missing heights, filled before the residual pyramid is encoded, so that
// every tile has a prediction to start from (doc/dem-encoding.md, "Nodata").
#pragma once
#include <optional>
#include <string>

#include "libpyramid/encode/residual/height_source.hpp"
#include "libpyramid/encode/residual/residual_tile.hpp"

namespace pyramid {

// Root-level nodata: a fixed number of Gauss-Seidel sweeps of Laplace's equation over the
// level-0 positions (with folded edges, its border positions too), from the mean of the valid
// ones (or of every valid grid sample when the root has none; or, when the grid has none
// either, of every valid finest sample, read from `heights` block by block on `threads`; or
// `emptyFill` when nothing is valid). Filled samples get valid = 2: encoded, but not counted as
// source. Throws Error naming `input` when no finest sample is valid and there is no `emptyFill`.
void fillRootNodata(const ResidualPlan& plan, SourceGrid& grid, const HeightSource& heights, int threads,
                    std::optional<float> emptyFill, const std::string& input);

} // namespace pyramid
