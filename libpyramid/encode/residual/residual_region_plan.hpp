// A region build of the residual encoder (doc/planet-scale.md, "One region at a time"): what it
// needs beyond the plan, checked before anything is written.
#pragma once
#include <optional>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"
#include "libpyramid/encode/residual/residual_tile.hpp"
#include "libpyramid/support/work_share.hpp"

namespace pyramid {

// What a region build needs beyond the plan: the region file's header, the subtrees below level
// C that reach the region, and from a parent, its scale and (for a root below level C) the
// reconstruction of the root's parent tile.
struct RegionBuild {
    RegionRoot root;
    ResidualHeader header; // the region file's, its scale set per attempt
    ShareRange range;
    std::optional<float> parentScale;
    std::vector<float> parentRecon;
    bool fromParent = false; // the region is encoded from parentRecon alone
};

// Checks a region build's options and its parent (one-line errors naming the option or the
// file), before anything is written: the parent must be a pyramid of this build, its shape and
// scale, and rebuild this input's `heights` over the root's quarter of its parent tile within
// scale / 2.
RegionBuild planRegion(const ResidualPlan& plan, const ResidualEncodeOptions& options, const HeightSource& heights);

} // namespace pyramid
