#include "libpyramid/encode/residual/residual_region_plan.hpp"

#include "formats/error.hpp"
#include "formats/residual_set.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

RegionBuild planRegion(const ResidualPlan& plan, const ResidualEncodeOptions& options) {
    const RegionRequest& region = *options.region;
    const RegionRoot& root = region.root;
    if (options.share) {
        failOption("region", "writes one region file; it is not built in parts (--part, mpirun)");
    }
    if (options.maxFileBytes > 0) {
        failOption("region", "writes one region file; --max-file-bytes cuts a whole pyramid into a set");
    }
    const int lowest = std::max(1, plan.minLevel);
    if (root.level < lowest || root.level > plan.M) {
        failOption("region", "tile " + tileText(root) + " cannot root a region: its level must be from " +
                                 std::to_string(lowest) + " to " + std::to_string(plan.M) +
                                 " (levels of full-size tiles, below the root)");
    }
    const int side = plan.tilesPerSide(root.level);
    if (root.tx < 0 || root.ty < 0 || root.tx >= side || root.ty >= side) {
        failOption("region", "tile " + tileText(root) + " is outside the pyramid (level " + std::to_string(root.level) +
                                 " has " + std::to_string(side) + " x " + std::to_string(side) + " tiles)");
    }
    if (options.autoScale && region.parent.empty()) {
        failOption("scale", "auto is the whole pyramid's choice, which one region cannot see: give the build's scale, "
                            "or --parent to take it from the main file");
    }
    RegionBuild r;
    r.root = root;
    r.header = residualRegionHeader(plan.header, root, plan.M);
    if (plan.C == plan.M) {
        r.range = ShareRange{0, 1, true};
    } else if (root.level <= plan.C) {
        const int k = plan.C + 1 - root.level;
        const auto begin =
            static_cast<int64_t>(mortonEncode(static_cast<uint32_t>(root.tx) << k, static_cast<uint32_t>(root.ty) << k));
        r.range = ShareRange{begin, begin + (int64_t{1} << (2 * k)), true};
    } else {
        const int k = root.level - plan.C - 1;
        const auto m =
            static_cast<int64_t>(mortonEncode(static_cast<uint32_t>(root.tx) >> k, static_cast<uint32_t>(root.ty) >> k));
        r.range = ShareRange{m, m + 1, true};
    }
    if (region.parent.empty()) {
        return r;
    }
    const PyramidSet set = openPyramidSet(region.parent);
    const auto mismatch = [&](const std::string& what) {
        failOption("parent", set.name() + " is not a pyramid of this build: " + what);
    };
    if (set.kind != PyramidKind::Residual) {
        mismatch("it holds orthos, not residuals");
    }
    const ResidualHeader parent = ResidualFileReader::readHeader(set.main);
    if (parent.rootLevel != 0) {
        mismatch("its main file " + set.main + " is a region file (root " +
                 tileText(RegionRoot{parent.rootLevel, parent.rootTx, parent.rootTy}) + ")");
    }
    if (parent.tileSize != plan.T || parent.minLevel != plan.minLevel) {
        mismatch("tileSize " + std::to_string(parent.tileSize) + " and minLevel " + std::to_string(parent.minLevel) +
                 ", not " + std::to_string(plan.T) + " and " + std::to_string(plan.minLevel));
    }
    const int deepest = setMaxLevel(set);
    if (deepest > plan.M) {
        mismatch("it has levels down to " + std::to_string(deepest) + ", this build to " + std::to_string(plan.M));
    }
    if (deepest < root.level - 1) {
        mismatch("it has levels down to " + std::to_string(deepest) + ", the region's root " + tileText(root) +
                 " needs level " + std::to_string(root.level - 1));
    }
    if (!options.autoScale && parent.scale != static_cast<float>(options.scale)) {
        mismatch("scale " + numberText(parent.scale) + ", not " + numberText(static_cast<float>(options.scale)));
    }
    r.parentScale = parent.scale;
    if (root.level > plan.C) {
        // The root's parent as the runtime rebuilds it: the encoder's reconstruction, bit for bit.
        const FileLevelProducer producer = makeSetLevelProducer(set, root.level - 1, 4);
        const auto tile = producer.fileTile(root.level - 1, root.tx >> 1, root.ty >> 1);
        const size_t samples = static_cast<size_t>(plan.tileIntervals(root.level - 1) + 5);
        if (tile->zf.size() != samples * samples) {
            mismatch("its tiles at level " + std::to_string(root.level - 1) + " have " + std::to_string(tile->size) +
                     " samples a side, not " + std::to_string(samples));
        }
        r.parentRecon = tile->zf;
        r.fromParent = true;
    }
    return r;
}

} // namespace pyramid
