#include "libpyramid/encode/ortho/ortho_region.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "formats/error.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/filters/colour_upsample.hpp"
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
    if (!parent.jpegBlockBound.empty()) {
        checkJpegParent(quarter, x0, y0);
        return;
    }
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

void OrthoRegionPlan::checkJpegParent(const Image8& quarter, int x0, int y0) const {
    // What the parent's encoder compressed over the quarter: its true colours at level 0, else
    // their residuals against its prediction from its own parent's rebuilt colours (the very
    // arithmetic of OrthoTileEncoder::encodeResidual); and the error the JPEG coding left in
    // them, summed in squares over each 8 x 8 block of the tile (the blocks JPEG codes alone).
    const int n = parent.tileSize, half = n / 2, c = parent.channels, side = n + 4;
    const int level = root.level - 1, ptx = root.tx >> 1, pty = root.ty >> 1;
    const size_t rowBytes = static_cast<size_t>(side) * static_cast<size_t>(c);
    const size_t quarterRow = static_cast<size_t>(half) * static_cast<size_t>(c);
    const int blocks = (side + 7) / 8;
    std::vector<double> squares(static_cast<size_t>(blocks) * static_cast<size_t>(blocks) * static_cast<size_t>(c));
    std::vector<uint8_t> prediction(rowBytes), residuals(quarterRow);
    for (int y = 0; y < half; ++y) {
        const int py = y0 + y;
        const uint8_t* expected = quarter.at(0, y);
        if (level > 0) {
            predictColourRow(parent.jpegGrandparent.data(), rowBytes, c, (ptx & 1) * half, (pty & 1) * half, py, side,
                             prediction.data());
            encodeColourResiduals(expected, prediction.data() + static_cast<size_t>(x0) * static_cast<size_t>(c),
                                  quarterRow, residuals.data());
            expected = residuals.data();
        }
        const uint8_t* stored = parent.jpegStored.data() + static_cast<size_t>(py) * rowBytes +
                                static_cast<size_t>(x0) * static_cast<size_t>(c);
        for (int i = 0; i < half; ++i) {
            const size_t block = static_cast<size_t>((py / 8) * blocks + (x0 + i) / 8);
            for (int ch = 0; ch < c; ++ch) {
                const size_t k = static_cast<size_t>(i) * static_cast<size_t>(c) + static_cast<size_t>(ch);
                const int d = int{stored[k]} - int{expected[k]};
                squares[block * static_cast<size_t>(c) + static_cast<size_t>(ch)] += static_cast<double>(d * d);
            }
        }
    }
    // The block furthest beyond its channel's bound (in root mean square over the 64 samples).
    double worst = 0.0, bound = 0.0, ratio = 0.0;
    for (size_t k = 0; k < squares.size(); ++k) {
        const double b = parent.jpegBlockBound[k % static_cast<size_t>(c)];
        const double e = std::sqrt(squares[k]);
        if (e / b > ratio) {
            ratio = e / b;
            worst = e / 8.0;
            bound = b / 8.0;
        }
    }
    if (ratio > 1.0) {
        char text[128];
        std::snprintf(text, sizeof text, "stored residuals off by %.1f in root mean square in an 8 x 8 JPEG block, "
                                         "beyond the %.1f its quantisation allows", worst, bound);
        failOption("parent", parent.name + " does not rebuild this input's colours at level " + std::to_string(level) +
                                 " (" + text + "): name the colour residuals of the same build, " + parent.expected);
    }
}

namespace {

// The bound a JPEG quantisation table sets on the error of one 8 x 8 block of decoded samples,
// as the root of the sum of its 64 squares. Each coefficient is off by at most half its divisor
// (the rounding of the quantisation), plus 1 for the integer forward DCT; the DCT is
// orthonormal, so the samples' errors have the same sum of squares as the coefficients'
// (Parseval); the integer inverse DCT and its rounding add at most 1 a sample, 8 over the block.
// Clamping the decoded samples to 0..255 only brings them nearer the coded ones, which lie there.
double jpegBlockBound(const std::array<uint16_t, 64>& table) {
    double sum = 0.0;
    for (const uint16_t q : table) {
        const double e = q / 2.0 + 1.0;
        sum += e * e;
    }
    return std::sqrt(sum) + 8.0;
}

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

// The colour reconstruction of the root's parent, as the runtime rebuilds it from `parent`
// (plan.parentRecon), and for a JPEG parent what checkJpegParent needs.
void readParent(const OrthoLevels& levels, const RegionRoot& root, const PyramidSet& set, OrthoRegionPlan& plan) {
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
    const int level = root.level - 1, ptx = root.tx >> 1, pty = root.ty >> 1;
    plan.parentRecon = *colours.tile(level, ptx, pty);
    if (!producer->hasTile(level, ptx, pty)) {
        return; // no stored residuals: the rebuilt colours are the prediction, checked as Deflate's
    }
    const std::string where = set.name() + ": tile " + tileText(RegionRoot{level, ptx, pty});
    const std::optional<JpegTileTables> jpeg = jpegTileTables(producer->rawTile(level, ptx, pty), where);
    if (!jpeg) {
        return;
    }
    if (jpeg->ycbcr || jpeg->components.size() != static_cast<size_t>(levels.channels())) {
        mismatch("its tiles are JPEG " + std::string(jpeg->ycbcr ? "in YCbCr" : "of other components") +
                 ", not colour residuals");
    }
    for (const std::array<uint16_t, 64>& table : jpeg->components) {
        plan.parent.jpegBlockBound.push_back(jpegBlockBound(table));
    }
    plan.parent.jpegStored = producer->tile(level, ptx, pty);
    if (level > 0) {
        plan.parent.jpegGrandparent = *colours.tile(level - 1, ptx >> 1, pty >> 1);
    }
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
        readParent(levels, root, set, plan);
        plan.parent.name = set.name();
        plan.parent.expected = "residuals/" + o.name + ".dat";
        plan.parent.colourSpace = o.levels.colourSpace;
        plan.parent.tileSize = levels.tileSize();
        plan.parent.channels = levels.channels();
        // Deflate residuals are lossless: the halved residual rebuilds each colour within 1, and
        // level 0 stores its colours. A JPEG parent is checked by its own tables (checkJpegParent).
        plan.parent.maxError = root.level == 1 ? 0 : 1;
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
