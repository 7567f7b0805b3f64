#include "libpyramid/encode/residual/residual_region_plan.hpp"

#include <cmath>

#include "formats/error.hpp"
#include "formats/residual_set.hpp"
#include "libpyramid/encode/residual/residual_reach.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

// The parent's heights over the root's quarter of its parent tile (`recon`, level L - 1, as the
// runtime rebuilds it) against this input's at the same positions: the parent of this build
// rebuilds them within scale / 2 (closed loop), a pyramid of other heights does not. Left
// unchecked where heights of level L - 1 do not reach the parent tile (a base coarser than that
// level, upsampled there) and at nodata.
void checkParentHeights(const ResidualPlan& plan, const RegionRoot& root, const std::vector<float>& recon,
                        float scale, const HeightSource& heights, const std::string& parentName) {
    const int p = root.level - 1;
    const int ptx = root.tx >> 1, pty = root.ty >> 1;
    if (p >= plan.minLevel && !tileReached(plan, heights, p, ptx, pty)) {
        return;
    }
    const int64_t half = plan.tileIntervals(root.level) / 2;
    const int64_t np = plan.tileIntervals(p);
    const int shift = plan.M - p;
    // Level-p positions [qx0, qx0 + half] x [qy0, qy0 + half]: the root's own, inside the map.
    const int64_t qx0 = static_cast<int64_t>(root.tx) * half, qy0 = static_cast<int64_t>(root.ty) * half;
    SourceGrid grid;
    grid.x0 = qx0 << shift;
    grid.y0 = qy0 << shift;
    grid.stride = int64_t{1} << shift;
    grid.nx = grid.ny = half + 1;
    heights.sample(grid);
    const auto side = static_cast<size_t>(np + 5);
    double worst = 0.0, bound = 0.0;
    int64_t worstX = 0, worstY = 0;
    for (int64_t j = 0; j <= half; ++j) {
        for (int64_t i = 0; i <= half; ++i) {
            const size_t k = static_cast<size_t>(j * grid.nx + i);
            if (!grid.valid[k]) {
                continue;
            }
            const auto si = static_cast<size_t>(qx0 + i - static_cast<int64_t>(ptx) * np + 2);
            const auto sj = static_cast<size_t>(qy0 + j - static_cast<int64_t>(pty) * np + 2);
            const float h = grid.height[k];
            const double d = std::fabs(static_cast<double>(recon[sj * side + si]) - static_cast<double>(h));
            // scale / 2, and the float32 rounding of a reconstruction at that height.
            const float magnitude = std::fabs(h) + scale;
            const double allowed = 0.5 * static_cast<double>(scale) +
                                   4.0 * static_cast<double>(std::nextafter(magnitude, INFINITY) - magnitude);
            if (d - allowed > worst - bound) {
                worst = d;
                bound = allowed;
                worstX = (qx0 + i) << shift;
                worstY = (qy0 + j) << shift;
            }
        }
    }
    if (worst > bound) {
        failOption("parent", parentName + " does not hold this input's heights at level " + std::to_string(p) +
                                 ": " + numberText(worst) + " from them at finest sample (" + std::to_string(worstX) +
                                 ", " + std::to_string(worstY) + "), beyond scale/2 = " + numberText(0.5 * scale) +
                                 ": name the main file of a build of the same input and options");
    }
}

} // namespace

RegionBuild planRegion(const ResidualPlan& plan, const ResidualEncodeOptions& options, const HeightSource& heights) {
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
    // The root's parent as the runtime rebuilds it: the encoder's reconstruction, bit for bit.
    const FileLevelProducer producer = makeSetLevelProducer(set, root.level - 1, 4);
    const auto tile = producer.fileTile(root.level - 1, root.tx >> 1, root.ty >> 1);
    const size_t samples = static_cast<size_t>(plan.tileIntervals(root.level - 1) + 5);
    if (tile->zf.size() != samples * samples) {
        mismatch("its tiles at level " + std::to_string(root.level - 1) + " have " + std::to_string(tile->size) +
                 " samples a side, not " + std::to_string(samples));
    }
    checkParentHeights(plan, root, tile->zf, parent.scale, heights, set.name());
    if (root.level > plan.C) {
        r.parentRecon = tile->zf;
        r.fromParent = true;
    }
    return r;
}

} // namespace pyramid
