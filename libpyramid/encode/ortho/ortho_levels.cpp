#include "libpyramid/encode/ortho/ortho_levels.hpp"

#include <algorithm>
#include <cmath>

#include "formats/error.hpp"
#include "libpyramid/encode/ortho/ortho_levels_impl.hpp"
#include "libpyramid/encode/ortho/face_pixels.hpp"
#include "libpyramid/encode/ortho/planar_pixels.hpp"
#include "libpyramid/encode/tile_size_rule.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

constexpr int kSubtreeDepth = 4;           // the coarse-first order's subtrees: levels C + 1..M, C = M - 4
constexpr int kSinglePassSubtreeDepth = 2; // the single pass's smallest subtrees (levels)
constexpr int64_t kSinglePassLevelBytes = int64_t{64} << 20;

} // namespace

OrthoTileFit fitOrthoTiles(int64_t side) {
    constexpr int64_t kLargest = 256;
    OrthoTileFit fit;
    while ((kLargest << fit.maxLevel) < side) {
        ++fit.maxLevel;
    }
    const int64_t level = int64_t{1} << fit.maxLevel;
    fit.tileSize = static_cast<int>(((side + level - 1) / level + 3) / 4 * 4);
    return fit;
}

void OrthoLevelsOptions::validate() const {
    if (fitTiles && maxLevel) {
        failOption("maxLevel", "is chosen with the tile size when the tiles are fitted to the input: give one or the other");
    }
    if (!fitTiles) {
        requireEncodableTileSize(tileSize); // a fitted one is (fitOrthoTiles)
    }
    if (maxLevel && (*maxLevel < 0 || *maxLevel > 20)) {
        failOption("maxLevel", std::to_string(*maxLevel) + " is outside 0..20");
    }
    workerThreads(threads); // refuses a count out of range
    requireCacheBudget(cacheMegabytes);
}


// The settings both geometries share: samples, channels, tile size and levels. By default the
// finest level is the first at least `wanted` pixels wide.
void OrthoLevels::Impl::init(const OrthoLevelsOptions& o, int64_t wanted) {
    const RasterInfo& info = source->info();
    const std::string& input = source->path();
    if (info.type != SampleType::UInt8 && info.type != SampleType::UInt16) {
        fail(input, "imagery must have 8- or 16-bit unsigned samples");
    }
    if (info.channels > 4 && !o.channels) {
        fail(input, std::to_string(info.channels) + " channels (1 to 4 expected; the channels option selects the first ones)");
    }
    if (o.channels && (*o.channels < 1 || *o.channels > std::min(4, info.channels))) {
        failOption("channels",
                   std::to_string(*o.channels) + " is not 1.." + std::to_string(std::min(4, info.channels)));
    }
    channels = o.channels.value_or(info.channels);
    T = o.tileSize;
    M = o.maxLevel.value_or(0);
    if (o.fitTiles) {
        const OrthoTileFit fit = fitOrthoTiles(wanted);
        T = fit.tileSize;
        M = fit.maxLevel;
    } else if (!o.maxLevel) {
        while ((static_cast<int64_t>(T) << M) < wanted) {
            ++M;
        }
    }
    if (M > 20) {
        failOption("maxLevel", std::to_string(M) + " is beyond 20");
    }
    C = std::max(0, M - kSubtreeDepth);
    // One pass assembles level C from the subtrees: subtrees of 2 or 3 levels rather than 4
    // start sooner on an input still being decoded (the first needs 2 (T + 4) or 4 (T + 4) of
    // its rows) and take a sixteenth or a quarter of the memory each, for a level C sixteen or
    // four times larger: the smallest whose level C stays within kSinglePassLevelBytes (a face's
    // level C has 2 << C pixels beyond each side: counted for a plane too, which errs on the
    // safe side).
    singlePassC = C;
    for (int depth = kSinglePassSubtreeDepth; depth < kSubtreeDepth && depth <= M; ++depth) {
        const int64_t side = static_cast<int64_t>(T + 4) << (M - depth);
        if (side * side * channels <= kSinglePassLevelBytes) {
            singlePassC = M - depth;
            break;
        }
    }
    averager = ColourAverager(o.colourSpace, channels);
    const Image8 black = averager.reduce(Image8(2, 2, channels));
    blankStaysBlank = std::all_of(black.pixels.begin(), black.pixels.end(), [](uint8_t v) { return v == 0; });
    zeroTile = Image8(T + 2 * kTileBorder, T + 2 * kTileBorder, channels);
    threads = workerThreads(o.threads);
}

void OrthoLevels::Impl::initPlanar(const OrthoLevelsOptions& o) {
    const RasterInfo& info = source->info();
    init(o, std::max(info.width, info.height));
    pixels = std::make_unique<PlanarPixels>(*source, channels, levelWidth(M), o.stretch);
    several = pixels->severalLevels();
}

OrthoLevels::OrthoLevels(const std::string& input, const OrthoLevelsOptions& o)
    : OrthoLevels(std::vector<std::string>{input}, o) {}

OrthoLevels::OrthoLevels(const std::vector<std::string>& inputs, const OrthoLevelsOptions& o)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    o.validate();
    m.ownedSource = openPlanarMosaic(inputs, o.cacheMegabytes, true, o.target);
    m.source = m.ownedSource.get();
    m.initPlanar(o);
}

OrthoLevels::OrthoLevels(const RasterSource& source, const OrthoLevelsOptions& o) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    o.validate();
    m.source = &source;
    m.initPlanar(o);
}

OrthoLevels::OrthoLevels(const RasterSource& source, const MapPlacement& placement, const PlanetBody& body, int face,
                         const OrthoLevelsOptions& o, const GeodeticMap* map)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    o.validate();
    if (o.fitTiles) {
        failOption("tileSize", "is fitted to planar inputs only: a cube face takes a number, e.g. 192");
    }
    if (o.tileSize < 4) {
        // The level images reach 4 / tileSize of a face beyond its edges; more than half a
        // face would fold past the neighbour face.
        failOption("tileSize", std::to_string(o.tileSize) + " is below 4, the smallest for a cube face");
    }
    m.source = &source;
    // A face spans a quarter of the equator. An image without georeferencing is taken as global
    // here whatever its extent (as before georeferencing was read); a georeferenced one by its
    // resolution.
    m.init(o, placement.crs.empty() ? (static_cast<int64_t>(source.info().width) + 3) / 4
                                    : static_cast<int64_t>(std::ceil(placement.columnsAround / 4.0)));
    m.pixels = std::make_unique<FacePixels>(source, placement, body, face, m.channels, m.levelWidth(m.M), map);
    m.several = m.pixels->severalLevels();
}

OrthoLevels::~OrthoLevels() = default;

int OrthoLevels::tileSize() const { return impl_->T; }
int OrthoLevels::maxLevel() const { return impl_->M; }
int OrthoLevels::channels() const { return impl_->channels; }
int OrthoLevels::inputWidth() const { return impl_->source->info().width; }
int OrthoLevels::inputHeight() const { return impl_->source->info().height; }
const std::string& OrthoLevels::inputPath() const { return impl_->source->path(); }
const RasterInfo& OrthoLevels::inputInfo() const { return impl_->source->info(); }
const std::string& OrthoLevels::sampling() const { return impl_->pixels->sampling(); }
int OrthoLevels::threads() const { return impl_->threads; }
int64_t OrthoLevels::tileCount() const { return ((int64_t{1} << (2 * (impl_->M + 1))) - 1) / 3; }

int OrthoLevels::topLevels(WalkOrder order) const {
    const Impl& m = *impl_;
    return order == WalkOrder::SinglePass && m.M > 0 ? m.singlePassC : m.C;
}

int64_t OrthoLevels::subtreeItems(WalkOrder order, bool pruned) const {
    const Impl& m = *impl_;
    pruned = pruned || m.several;
    if (order == WalkOrder::SinglePass && m.M > 0) {
        return pruned ? static_cast<int64_t>(m.prunedItems(m.singlePassC, false).size())
                      : int64_t{1} << (2 * (m.singlePassC + 1));
    }
    if (m.C == m.M) {
        return 0;
    }
    return pruned ? static_cast<int64_t>(m.prunedItems(m.C, true).size()) : int64_t{1} << (2 * (m.C + 1));
}

bool OrthoLevels::reachesEveryTopTile() const {
    const Impl& m = *impl_;
    return !m.several &&
           (m.C == m.M || subtreeItems(WalkOrder::CoarseFirst, true) == subtreeItems(WalkOrder::CoarseFirst));
}

bool OrthoLevels::severalLevels() const { return impl_->several; }

bool OrthoLevels::isFace() const {
    return impl_->margin(0) > 0;
}

int64_t OrthoLevels::itemWindow() const {
    return std::max<int64_t>(4, 2 * impl_->threads);
}

int64_t OrthoLevels::walk(const Sink& sink, WalkOrder order, const Range* range, bool pruned) const {
    const Impl& m = *impl_;
    pruned = pruned || m.several;
    const int64_t items = subtreeItems(order, pruned);
    const int64_t begin = range ? range->begin : 0, end = range ? range->end : items;
    const int64_t subtrees = end - begin;
    if (order == WalkOrder::SinglePass && m.M > 0) {
        // The subtrees first, row by row from the north edge, west to east, so that an input
        // still being decoded from its first row is worked on as it arrives; each leaves its
        // share of level C (a face's margin beyond it comes from bands of its own), and levels
        // 0..C come last.
        const int c = m.singlePassC;
        const Impl::ItemList* list = pruned ? &m.prunedItems(c, false) : nullptr;
        // A share without every subtree takes levels 0..C from bands instead; a walk without
        // them does not assemble level C.
        const bool whole = begin == 0 && end == items && (!range || range->top) && !m.several;
        const BlockMask reach = m.reachOf(c);
        std::vector<SparseLevel> levels(static_cast<size_t>(c) + 1);
        SparseLevel& levelC = levels[static_cast<size_t>(c)];
        if (whole) {
            levelC = SparseLevel(m.sideWithMargin(c), m.channels, reach);
        }
        // The input lets go of the rows the subtrees pass only when it is this object's own (a
        // caller's source may be read again).
        const bool passRows = sink.lastRead && whole && list == nullptr && m.ownedSource != nullptr;
        if (!m.handSubtrees(sink, c + 1, begin, end, 0, false, reach, whole ? &levelC : nullptr, list, passRows) ||
            (range && !range->top)) {
            return subtrees;
        }
        if (whole) {
            if (m.margin(c) > 0) {
                m.marginFromBands(c, levelC);
            }
            m.reduceCoarserLevels(levels);
        } else {
            levels = m.coarseLevelsFromBands(c, reach);
        }
        m.handLevels(levels, sink, subtrees, pruned);
        return subtrees + c + 1;
    }
    // Levels 0..C from one pass over the input, then the subtrees of level C + 1 in Z order,
    // each from its own footprint: every tile comes after its parent.
    const BlockMask reach = m.reachOf(m.C);
    if (m.handLevels(m.coarseLevelsFromBands(m.C, reach), sink, 0, pruned) && m.C < m.M) {
        m.handSubtrees(sink, m.C + 1, begin, end, m.C + 1, true, reach, nullptr,
                       pruned ? &m.prunedItems(m.C, true) : nullptr);
    }
    return m.C + 1 + subtrees;
}

} // namespace pyramid
