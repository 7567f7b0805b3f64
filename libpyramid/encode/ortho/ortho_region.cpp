#include "libpyramid/encode/ortho/ortho_region.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "formats/error.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/support/morton.hpp"

namespace pyramid {

bool OrthoRegionPlan::needed(int level, int tx, int ty) const {
    if (holds(level, tx, ty)) {
        return true;
    }
    return ancestors && level < root.level && regionHolds(RegionRoot{level, tx, ty}, root.level, root.tx, root.ty);
}

void OrthoRegionPlan::checkParent(const TrueTile& t) const {
    if (parentRecon.empty()) {
        return;
    }
    const int n = parent.tileSize, half = n / 2, c = parent.channels;
    const auto rowBytes = static_cast<size_t>(n) * static_cast<size_t>(c);
    const Image8& tile = t.image();
    Image8 interior(n, n, c, Image8::Unset);
    for (int y = 0; y < n; ++y) {
        std::copy_n(tile.at(2, y + 2), rowBytes, interior.at(0, y));
    }
    const Image8 quarter = ColourAverager(parent.colourSpace, c).reduce(interior);
    // The quarter of the parent over the root, in the parent's (tileSize + 4)^2 tile with its border.
    const int x0 = 2 + (root.tx & 1) * half, y0 = 2 + (root.ty & 1) * half;
    const auto side = static_cast<size_t>(n + 4);
    int worst = 0;
    for (int y = 0; y < half; ++y) {
        const uint8_t* rebuilt = parentRecon.data() + ((static_cast<size_t>(y0 + y) * side) + static_cast<size_t>(x0)) *
                                                          static_cast<size_t>(c);
        const uint8_t* truth = quarter.at(0, y);
        for (size_t k = 0; k < static_cast<size_t>(half) * static_cast<size_t>(c); ++k) {
            worst = std::max(worst, std::abs(int{rebuilt[k]} - int{truth[k]}));
        }
    }
    if (worst > parent.maxError) {
        failOption("parent", parent.name + " does not rebuild this input's colours at level " +
                                 std::to_string(root.level - 1) + " (max error " + std::to_string(worst) +
                                 ", beyond the residuals' " + std::to_string(parent.maxError) +
                                 "): name the colour residuals of the same build, " + parent.expected);
    }
}

namespace {

// The items of a CoarseFirst walk (subtrees of level C + 1 in Z order) that reach the region.
OrthoLevels::Range coarseFirstRange(const OrthoLevels& levels, const RegionRoot& root) {
    const int c = levels.topLevels(OrthoLevels::WalkOrder::CoarseFirst);
    if (levels.subtreeItems(OrthoLevels::WalkOrder::CoarseFirst) == 0) {
        return {0, 0, true}; // the top levels are the whole pyramid
    }
    if (root.level <= c) {
        // Its descendants at level C + 1: one run of the Z order.
        const int k = c + 1 - root.level;
        const auto begin =
            static_cast<int64_t>(mortonEncode(static_cast<uint32_t>(root.tx) << k, static_cast<uint32_t>(root.ty) << k));
        return {begin, begin + (int64_t{1} << (2 * k)), true};
    }
    const int k = root.level - c - 1;
    const auto item =
        static_cast<int64_t>(mortonEncode(static_cast<uint32_t>(root.tx) >> k, static_cast<uint32_t>(root.ty) >> k));
    return {item, item + 1, true};
}

// The colour reconstruction of the root's parent, as the runtime rebuilds it from `parent`.
std::vector<uint8_t> parentReconstruction(const OrthoLevels& levels, const RegionRoot& root, const PyramidSet& set) {
    const auto mismatch = [&](const std::string& what) {
        failOption("parent", set.name() + " is not the colour residuals of this build: " + what);
    };
    if (set.kind != PyramidKind::Ortho) {
        mismatch("it holds elevation residuals");
    }
    const auto producer = openOrthoSet(set);
    const OrthoHeader& h = producer->header();
    if (h.rootLevel != 0) {
        mismatch("its main file " + set.main + " is a region file (root " +
                 tileText(RegionRoot{h.rootLevel, h.rootTx, h.rootTy}) + ")");
    }
    if (h.dxt() || h.border() != 2) {
        mismatch("its tiles are " + std::string(h.dxt() ? "DXT" : "without borders") + ", not colour residuals");
    }
    if (h.tileSize != levels.tileSize() || h.channels != levels.channels()) {
        mismatch("tileSize " + std::to_string(h.tileSize) + " and " + std::to_string(h.channels) + " channels, not " +
                 std::to_string(levels.tileSize()) + " and " + std::to_string(levels.channels()));
    }
    const int deepest = producer->maxLevel();
    if (deepest > levels.maxLevel()) {
        mismatch("it has levels down to " + std::to_string(deepest) + ", this build to " +
                 std::to_string(levels.maxLevel()));
    }
    if (deepest < root.level - 1) {
        mismatch("it has levels down to " + std::to_string(deepest) + ", the region's root " + tileText(root) +
                 " needs level " + std::to_string(root.level - 1));
    }
    ColourProducer colours(producer, 4);
    return *colours.tile(root.level - 1, root.tx >> 1, root.ty >> 1);
}

} // namespace

OrthoRegionPlan planOrthoRegion(const OrthoLevels& levels, const OrthoEncodeOptions& o) {
    const RegionRequest& request = *o.region;
    const RegionRoot& root = request.root;
    if (o.share) {
        failOption("region", "writes one region of each output; it is not built in parts (--part, mpirun)");
    }
    if (o.maxFileBytes > 0) {
        failOption("region", "writes one region of each output; --max-file-bytes cuts a whole pyramid into sets");
    }
    const int m = levels.maxLevel();
    if (root.level < 1 || root.level > m) {
        failOption("region", "tile " + tileText(root) + " cannot root a region: its level must be from 1 to " +
                                 std::to_string(m) + " (maxLevel)");
    }
    const int64_t side = int64_t{1} << root.level;
    if (root.tx < 0 || root.ty < 0 || root.tx >= side || root.ty >= side) {
        failOption("region", "tile " + tileText(root) + " is outside the pyramid (level " + std::to_string(root.level) +
                                 " has " + std::to_string(side) + " tiles a side)");
    }
    if (!request.parent.empty() && !o.writeResiduals) {
        failOption("parent", "gives the colour residuals' enclosing pyramid, and this build writes no residuals");
    }
    OrthoRegionPlan plan;
    plan.root = root;
    plan.tiles = ((int64_t{1} << (2 * (m - root.level + 1))) - 1) / 3;
    if (o.writeResiduals && request.parent.empty()) {
        // The root's parent comes from the input: every level above it, as the whole build.
        plan.order = OrthoLevels::WalkOrder::CoarseFirst;
        plan.range = coarseFirstRange(levels, root);
        plan.ancestors = true;
        return plan;
    }
    if (o.writeResiduals) {
        const PyramidSet set = openPyramidSet(request.parent);
        plan.parentRecon = parentReconstruction(levels, root, set);
        plan.parent.name = set.name();
        plan.parent.expected = "residuals/" + o.name + ".dat";
        plan.parent.colourSpace = o.levels.colourSpace;
        plan.parent.tileSize = levels.tileSize();
        plan.parent.channels = levels.channels();
        // Deflate residuals are lossless: the halved residual rebuilds each colour within 1, and
        // level 0 stores its colours. JPEG's loss has no bound known ahead (the report measures
        // it afterwards): such a parent is not checked.
        const bool jpeg = o.residualCompression == TilePolicy::Jpeg;
        plan.parent.maxError = jpeg ? 255 : root.level == 1 ? 0 : 1;
    }
    const int c = levels.topLevels(OrthoLevels::WalkOrder::SinglePass);
    if (root.level > c && levels.subtreeItems(OrthoLevels::WalkOrder::SinglePass) > 0) {
        // Within one subtree of the single pass: its footprint is all the input it reads. Items
        // run row by row from the north edge, west to east.
        const int top = c + 1, k = root.level - top;
        const int64_t tiles = int64_t{1} << top;
        const int64_t item = (tiles - 1 - (root.ty >> k)) * tiles + (root.tx >> k);
        plan.order = OrthoLevels::WalkOrder::SinglePass;
        plan.range = {item, item + 1, false};
        return plan;
    }
    // A root within the top levels: they are computed from the whole input.
    plan.order = OrthoLevels::WalkOrder::CoarseFirst;
    plan.range = coarseFirstRange(levels, root);
    return plan;
}

} // namespace pyramid
