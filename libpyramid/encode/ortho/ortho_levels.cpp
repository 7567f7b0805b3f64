#include "libpyramid/encode/ortho/ortho_levels.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <mutex>
#include <tuple>

#include "formats/error.hpp"
#include "libpyramid/encode/ortho/face_pixels.hpp"
#include "libpyramid/encode/ortho/planar_pixels.hpp"
#include "libpyramid/encode/ortho/sparse_level.hpp"
#include "libpyramid/encode/tile_size_rule.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "libpyramid/support/box_quarters.hpp"
#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

constexpr int kSubtreeDepth = 4;           // the coarse-first order's subtrees: levels C + 1..M, C = M - 4
constexpr int kSinglePassSubtreeDepth = 2; // the single pass's smallest subtrees (levels)
constexpr int64_t kSinglePassLevelBytes = int64_t{64} << 20;

} // namespace

void OrthoLevelsOptions::validate() const {
    requireEncodableTileSize(tileSize);
    if (maxLevel && (*maxLevel < 0 || *maxLevel > 20)) {
        failOption("maxLevel", std::to_string(*maxLevel) + " is outside 0..20");
    }
    workerThreads(threads); // refuses a count out of range
    requireCacheBudget(cacheMegabytes);
}

struct OrthoLevels::Impl {
    std::unique_ptr<RasterSource> ownedSource; // planar: opened here
    const RasterSource* source = nullptr;
    std::unique_ptr<PixelSource> pixels;       // the plane's or the face's finest pixels
    int T = 0, M = 0, C = 0, channels = 0;
    int singlePassC = 0; // C of WalkOrder::SinglePass
    ColourAverager averager{ColourSpace::Srgb, 1};
    int threads = 1;
    bool blankStaysBlank = false; // averaging black and transparent pixels gives them again
    Image8 zeroTile;              // the pixels of every blank tile (TrueTile::image)

    void init(const OrthoLevelsOptions& o, int64_t wanted);
    // init() of a plane: the finest level holds the source's longer side.
    void initPlanar(const OrthoLevelsOptions& o) {
        const RasterInfo& info = source->info();
        init(o, std::max(info.width, info.height));
        pixels = std::make_unique<PlanarPixels>(*source, channels, levelWidth(M), o.stretch);
    }

    int64_t levelWidth(int l) const { return static_cast<int64_t>(T) << l; }

    // Pixels computed beyond each side of level l when it is built whole (PixelSource::margin).
    int64_t margin(int l) const { return pixels->margin(l); }

    // Tile (l, tx, ty) with its border from `img`, whose pixel (0, 0) is level-l pixel (ox, oy).
    TrueTile extract(const Image8& img, int64_t ox, int64_t oy, int l, int tx, int ty) const {
        return cut(l, tx, ty, ox, oy, [&](int64_t x, int64_t y, int n, uint8_t* out) {
            std::copy_n(img.at(static_cast<int>(x), static_cast<int>(y)), static_cast<size_t>(n) * channels, out);
        });
    }
    // The same from a level of 0..C, whose pixel (0, 0) is level-l pixel (-margin(l), -margin(l)):
    // a blank tile when no block of the level under it is stored.
    TrueTile extract(const SparseLevel& level, int l, int tx, int ty) const {
        const int64_t o = -margin(l), width = levelWidth(l);
        const int64_t first = static_cast<int64_t>(T) * tx - kTileBorder, last = static_cast<int64_t>(T) * (tx + 1) + kTileBorder - 1;
        const int64_t bottom = static_cast<int64_t>(T) * ty - kTileBorder, top = static_cast<int64_t>(T) * (ty + 1) + kTileBorder - 1;
        if (level.blank(pixels->borderPixel(first, width) - o, pixels->borderPixel(bottom, width) - o,
                        pixels->borderPixel(last, width) - o, pixels->borderPixel(top, width) - o)) {
            return blankTile(l, tx, ty);
        }
        return cut(l, tx, ty, o, o, [&](int64_t x, int64_t y, int n, uint8_t* out) { level.read(x, y, n, out); });
    }
    TrueTile blankTile(int l, int tx, int ty) const {
        // Not a tile of 0s each: a face a small map barely touches has hundreds of thousands.
        return TrueTile::blankAt(l, tx, ty, &zeroTile);
    }
    // Tile (l, tx, ty) with its border, from `read(x, y, n, out)`, which gives n pixels from
    // (x, y) of an image whose pixel (0, 0) is level-l pixel (ox, oy).
    template <class Read>
    TrueTile cut(int l, int tx, int ty, int64_t ox, int64_t oy, const Read& read) const {
        TrueTile t;
        t.level = l;
        t.tx = tx;
        t.ty = ty;
        const int side = T + 2 * kTileBorder;
        t.pixels = Image8(side, side, channels, Image8::Unset); // every pixel is copied below
        // The columns are the same for every row: runs of consecutive source columns (all of
        // them but clamped edge pixels) are copied as one block.
        const int64_t width = levelWidth(l);
        std::vector<int64_t> gx(static_cast<size_t>(side));
        for (int x = 0; x < side; ++x) {
            gx[static_cast<size_t>(x)] = pixels->borderPixel(static_cast<int64_t>(tx) * T + x - kTileBorder, width) - ox;
        }
        for (int y = 0; y < side; ++y) {
            const int64_t gy = pixels->borderPixel(static_cast<int64_t>(ty) * T + y - kTileBorder, width) - oy;
            for (int x = 0; x < side;) {
                int run = 1;
                while (x + run < side && gx[static_cast<size_t>(x + run)] == gx[static_cast<size_t>(x)] + run) {
                    ++run;
                }
                read(gx[static_cast<size_t>(x)], gy, run, t.pixels.at(x, y));
                x += run;
            }
        }
        return t;
    }

    // Finest pixels [x0, x0+w) x [y0, y0+h) reduced `times` times (w and h multiples of 2^times).
    Image8 reducedFinest(int64_t x0, int64_t y0, int w, int h, int times) const {
        if (blankStaysBlank && pixels->knownBlank(x0, y0, w, h)) {
            return Image8(w >> times, h >> times, channels); // what reducing the 0s gives
        }
        Image8 img = pixels->sample(x0, y0, w, h);
        for (int r = 0; r < times; ++r) {
            img = averager.reduce(img);
        }
        return img;
    }

    int64_t sideWithMargin(int c) const { return levelWidth(c) + 2 * margin(c); }
    // The pixel rows of `level` that meet a stored block, from the top (north) down: the rows a
    // pass over the input in bands samples (the others are 0 and stay so).
    static std::vector<int64_t> storedRowsFromTop(const SparseLevel& level) {
        std::vector<int64_t> rows;
        for (const int64_t by : level.mask().rowsFromTop()) {
            for (int64_t row = std::min(level.side(), (by + 1) * kSparseBlock) - 1; row >= by * kSparseBlock; --row) {
                rows.push_back(row);
            }
        }
        return rows;
    }
    BlockMask reachOf(int c) const;
    void bandInto(SparseLevel& level, int c, int64_t row, int64_t x0, int64_t x1) const;
    std::vector<SparseLevel> coarseLevelsFromBands(int c, const BlockMask& reach) const;
    void reduceCoarserLevels(std::vector<SparseLevel>& levels) const;
    bool handLevels(const std::vector<SparseLevel>& levels, const Sink& sink, int64_t index0, bool pruned) const;
    // The subtree items of a walk: all of level `top` (row by row or in Z order), or with `items`
    // those it lists.
    using ItemList = std::vector<std::pair<int, int>>;
    bool handSubtrees(const Sink& sink, int top, int64_t begin, int64_t end, int64_t index0, bool zOrder,
                      const BlockMask& reachC, SparseLevel* levelC, const ItemList* items) const;
    void subtreeFromFootprint(int top, int tx, int ty, TileBatch& out, const BlockMask& reachC,
                              SparseLevel* levelC, bool pruned) const;
    ItemList itemsUnder(int c, const BlockMask& reach, bool zOrder) const;
    // A pruned walk's items in `order` (computed once per order).
    const ItemList& prunedItems(int c, bool zOrder) const {
        const std::lock_guard<std::mutex> lock(itemsMutex);
        auto it = itemLists.find(zOrder);
        if (it == itemLists.end()) {
            it = itemLists.emplace(zOrder, itemsUnder(c, reachOf(c), zOrder)).first;
        }
        return it->second;
    }
    mutable std::mutex itemsMutex;
    mutable std::map<bool, ItemList> itemLists; // by zOrder
    void marginFromBands(int c, SparseLevel& levelC) const;
    void blankSubtree(int l, int tx, int ty, TileBatch& out) const;

    void subtree(int top, int l, int tx, int ty, const std::vector<Image8>& imgs, const std::vector<int64_t>& ox,
                 const std::vector<int64_t>& oy, TileBatch& out) const {
        const size_t k = static_cast<size_t>(l - top);
        out.push_back(extract(imgs[k], ox[k], oy[k], l, tx, ty));
        if (l < M) {
            for (int c = 0; c < 4; ++c) {
                subtree(top, l + 1, 2 * tx + (c & 1), 2 * ty + (c >> 1), imgs, ox, oy, out);
            }
        }
    }
};

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
    if (!o.maxLevel) {
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

// The blocks of level c whole (a face's margin included) whose finest pixels the input may
// reach, those a SparseLevel of it stores: every block unless the average of 0s is 0. Found by
// halving the level's blocks as long as a part is not known blank, so that a face a small map
// barely touches asks its pixel source a few hundred times, not once per block.
BlockMask OrthoLevels::Impl::reachOf(int c) const {
    const int k = M - c;
    const int64_t mc = margin(c);
    const int64_t side = sideWithMargin(c);
    const int64_t across = BlockMask::blocks(side);
    BlockMask stored(side, blankStaysBlank ? 0 : 1);
    if (blankStaysBlank) {
        const auto mark = [&](const auto& self, int64_t bx0, int64_t by0, int64_t bx1, int64_t by1) -> void {
            const int64_t x0 = bx0 * kSparseBlock, y0 = by0 * kSparseBlock;
            const int64_t x1 = std::min(side, bx1 * kSparseBlock), y1 = std::min(side, by1 * kSparseBlock);
            if (pixels->knownBlank((x0 - mc) << k, (y0 - mc) << k, (x1 - x0) << k, (y1 - y0) << k)) {
                return;
            }
            if (bx1 - bx0 == 1 && by1 - by0 == 1) {
                stored.store(bx0, by0);
                return;
            }
            forEachQuarter(bx0, by0, bx1, by1,
                           [&](int64_t a0, int64_t b0, int64_t a1, int64_t b1) { self(self, a0, b0, a1, b1); });
        };
        mark(mark, 0, 0, across, across);
        stored.seal();
    }
    return stored;
}

// Row `row` of level c between columns [x0, x1) (the level's pixels, a face's margin from 0),
// each pixel the reduction of its 2^(M-c) x 2^(M-c) finest block, written into `level`: only
// its stored blocks are sampled, in runs of neighbouring ones.
void OrthoLevels::Impl::bandInto(SparseLevel& level, int c, int64_t row, int64_t x0, int64_t x1) const {
    const int k = M - c;
    const int64_t mc = margin(c);
    level.mask().forEachRun(row / kSparseBlock, x0 / kSparseBlock, (x1 + kSparseBlock - 1) / kSparseBlock,
                            [&](int64_t first, int64_t end) {
                                const int64_t from = std::max(x0, first * kSparseBlock);
                                const int64_t to = std::min(x1, end * kSparseBlock);
                                if (from < to) {
                                    level.write(reducedFinest((from - mc) << k, (row - mc) << k,
                                                              static_cast<int>((to - from) << k), 1 << k, k),
                                                from, row);
                                }
                            });
}

// Levels 0..C, from bands of 2^(M-C) finest rows, a face's margin included; northern rows
// first, so that an input still being decoded from its first row (PNG) is worked on as it
// arrives.
std::vector<SparseLevel> OrthoLevels::Impl::coarseLevelsFromBands(int c, const BlockMask& reach) const {
    std::vector<SparseLevel> levels(static_cast<size_t>(c) + 1);
    SparseLevel& levelC = levels[static_cast<size_t>(c)];
    levelC = SparseLevel(sideWithMargin(c), channels, reach);
    const int64_t sideC = levelC.side();
    const std::vector<int64_t> rows = storedRowsFromTop(levelC);
    parallelFor(static_cast<int64_t>(rows.size()), threads,
                [&](int64_t i) { bandInto(levelC, c, rows[static_cast<size_t>(i)], 0, sideC); });
    reduceCoarserLevels(levels);
    return levels;
}

void OrthoLevels::Impl::reduceCoarserLevels(std::vector<SparseLevel>& levels) const {
    for (int l = static_cast<int>(levels.size()) - 2; l >= 0; --l) {
        levels[static_cast<size_t>(l)] = levels[static_cast<size_t>(l) + 1].reduced(averager, threads);
    }
}

// One item per level 0..C, each level's tiles in Z order, numbered from `index0`. False when
// the sink stops the walk. Pruned: only the tiles under tiles that are not blank (and the root).
bool OrthoLevels::Impl::handLevels(const std::vector<SparseLevel>& levels, const Sink& sink, int64_t index0,
                                   bool pruned) const {
    std::vector<uint64_t> open{0}; // pruned: the Morton codes of the level's tiles handed out
    for (int l = 0; l < static_cast<int>(levels.size()); ++l) {
        const int side = 1 << l;
        const int64_t count = pruned ? static_cast<int64_t>(open.size()) : int64_t{side} * side;
        TileBatch batch(static_cast<size_t>(count));
        parallelFor(count, threads, [&](int64_t i) {
            const uint64_t code = pruned ? open[static_cast<size_t>(i)] : static_cast<uint64_t>(i);
            const auto [tx, ty] = mortonDecode(code);
            TrueTile& t = batch[static_cast<size_t>(i)];
            t = extract(levels[static_cast<size_t>(l)], l, static_cast<int>(tx), static_cast<int>(ty));
            t.blankBelow = pruned && l > 0 && t.blank;
        });
        if (pruned) {
            std::vector<uint64_t> next;
            for (size_t i = 0; i < batch.size(); ++i) {
                if (!batch[i].blankBelow) {
                    for (uint64_t k = 0; k < 4; ++k) {
                        next.push_back(4 * open[i] + k); // the children, in Z order
                    }
                }
            }
            open = std::move(next);
        }
        if (!sink.level(index0 + l, batch)) {
            return false;
        }
    }
    return true;
}

// The level-(c+1) items of a pruned walk: the children of the level-c tiles whose footprint (the
// tile and its border) a block of `reach` meets, those a pruned walk hands out not blank (the
// root, when c = 0, whatever it holds). Found by halving squares of tiles, so that a face a
// small map barely touches costs a few hundred questions. In Z order, or row by row from the
// north edge, west to east.
OrthoLevels::Impl::ItemList OrthoLevels::Impl::itemsUnder(int c, const BlockMask& reach, bool zOrder) const {
    const int64_t width = levelWidth(c), m = margin(c);
    const auto px = [&](int64_t p) { return pixels->borderPixel(p, width) + m; };
    ItemList tiles;
    const auto visit = [&](const auto& self, int64_t x0, int64_t y0, int64_t side) -> void {
        if (c > 0 && !reach.meets(px(x0 * T - kTileBorder), px(y0 * T - kTileBorder),
                                  px((x0 + side) * T + kTileBorder - 1), px((y0 + side) * T + kTileBorder - 1))) {
            return;
        }
        if (side == 1) {
            tiles.emplace_back(static_cast<int>(x0), static_cast<int>(y0));
            return;
        }
        const int64_t h = side / 2;
        self(self, x0, y0, h);
        self(self, x0 + h, y0, h);
        self(self, x0, y0 + h, h);
        self(self, x0 + h, y0 + h, h);
    };
    visit(visit, 0, 0, int64_t{1} << c);
    ItemList items;
    items.reserve(4 * tiles.size());
    for (const auto& [tx, ty] : tiles) {
        for (int k = 0; k < 4; ++k) {
            items.emplace_back(2 * tx + (k & 1), 2 * ty + (k >> 1));
        }
    }
    if (!zOrder) {
        std::sort(items.begin(), items.end(), [](const auto& a, const auto& b) {
            return a.second != b.second ? a.second > b.second : a.first < b.first;
        });
    }
    return items;
}

// The subtrees [begin, end) of level `top` (row by row from the north edge, west to east, or in
// Z order), numbered from `index0`, each sampled and handed to the sink by a free thread, in
// order. False when the sink stops the walk.
bool OrthoLevels::Impl::handSubtrees(const Sink& sink, int top, int64_t begin, int64_t end, int64_t index0,
                                     bool zOrder, const BlockMask& reachC, SparseLevel* levelC,
                                     const ItemList* items) const {
    const int side = 1 << top;
    std::atomic<bool> stop{false};
    parallelFor(end - begin, threads, [&](int64_t i) {
        if (stop.load(std::memory_order_relaxed)) {
            return;
        }
        const int64_t n = begin + i;
        int tx = static_cast<int>(n % side), ty = side - 1 - static_cast<int>(n / side);
        if (items != nullptr) {
            std::tie(tx, ty) = (*items)[static_cast<size_t>(n)];
        } else if (zOrder) {
            const auto [zx, zy] = mortonDecode(static_cast<uint64_t>(n));
            tx = static_cast<int>(zx);
            ty = static_cast<int>(zy);
        }
        try {
            TileBatch item;
            subtreeFromFootprint(top, tx, ty, item, reachC, levelC, items != nullptr);
            if (!sink.subtree(index0 + i, item)) {
                stop = true;
            }
        } catch (...) {
            stop = true;
            if (sink.failed) {
                sink.failed(index0 + i);
            }
            throw;
        }
    });
    return !stop;
}

// The subtree of level-(C+1) tile (tx, ty), from its own footprint of the input; `reachC`, the
// blocks of level C the input may reach (reachOf). With `levelC`, also the level-C pixels under
// the tile (its interior reduced once more) are stored there.
void OrthoLevels::Impl::subtreeFromFootprint(int top, int tx, int ty, TileBatch& out, const BlockMask& reachC,
                                             SparseLevel* levelC, bool pruned) const {
    const int d = M - top;
    // The tile and its border, within the pixels the source has at level `top`: a plane's
    // footprint stops at the map's edge (whose pixels repeat), a face's reaches into its margin
    // beyond the edge (which is wider than the border).
    const int64_t lo = -margin(top);
    const int64_t hi = levelWidth(top) + margin(top);
    const int64_t x0 = std::max<int64_t>(lo, static_cast<int64_t>(tx) * T - kTileBorder);
    const int64_t y0 = std::max<int64_t>(lo, static_cast<int64_t>(ty) * T - kTileBorder);
    const int64_t x1 = std::min<int64_t>(hi, (static_cast<int64_t>(tx) + 1) * T + kTileBorder);
    const int64_t y1 = std::min<int64_t>(hi, (static_cast<int64_t>(ty) + 1) * T + kTileBorder);
    // Wholly beyond the input: under level-C blocks it cannot reach (the footprint's level-C
    // pixels, a face's margin from 0), or found so by the pixel source for the footprint itself.
    const int64_t mc = margin(top - 1);
    const bool unreached = !reachC.meets((x0 >> 1) + mc, (y0 >> 1) + mc, ((x1 - 1) >> 1) + mc, ((y1 - 1) >> 1) + mc);
    if (blankStaysBlank && (unreached || pixels->knownBlank(x0 << d, y0 << d, (x1 - x0) << d, (y1 - y0) << d))) {
        // Wholly beyond the input: every pixel of every level is 0 (and so is levelC, as
        // created). No sampling, no reduction; a pruned walk hands out the root alone.
        if (pruned) {
            out.push_back(blankTile(top, tx, ty));
            out.back().blankBelow = true;
            return;
        }
        blankSubtree(top, tx, ty, out);
        return;
    }
    // Images of levels top..M over the footprint, finest first, then reduced upwards.
    std::vector<Image8> imgs(static_cast<size_t>(d) + 1);
    std::vector<int64_t> ox(imgs.size()), oy(imgs.size());
    imgs[static_cast<size_t>(d)] =
        pixels->sample(x0 << d, y0 << d, static_cast<int>((x1 - x0) << d), static_cast<int>((y1 - y0) << d));
    for (int j = d; j >= 0; --j) {
        ox[static_cast<size_t>(j)] = x0 << j;
        oy[static_cast<size_t>(j)] = y0 << j;
        if (j < d) {
            imgs[static_cast<size_t>(j)] = averager.reduce(imgs[static_cast<size_t>(j) + 1]);
        }
    }
    subtree(top, top, tx, ty, imgs, ox, oy, out);
    if (levelC != nullptr) {
        // Level C is the 2x2 average of level C + 1, block by block: the tile's T x T interior
        // (T is even) gives the T/2 x T/2 level-C pixels under it, the same values as reducing
        // the whole of level C + 1.
        Image8 interior(T, T, channels, Image8::Unset);
        const size_t rowBytes = static_cast<size_t>(T) * channels;
        for (int y = 0; y < T; ++y) {
            std::copy_n(imgs[0].at(static_cast<int>(int64_t{tx} * T - x0), static_cast<int>(int64_t{ty} * T - y0 + y)),
                        rowBytes, interior.at(0, y));
        }
        levelC->write(averager.reduce(interior), mc + int64_t{tx} * (T / 2), mc + int64_t{ty} * (T / 2));
    }
}

// The level-c pixels beyond the map's edge (PixelSource::margin: a face's 2 << c pixels on each
// side), each the reduction of its 2^k x 2^k finest block as in coarseLevelsFromBands: the rows
// wholly in the margin from bands across the whole width, the other rows' margin columns from
// bands as wide as the margin. The pixels over the map itself come from the subtrees.
void OrthoLevels::Impl::marginFromBands(int c, SparseLevel& levelC) const {
    const int64_t mc = margin(c);
    const int64_t inner = levelWidth(c);
    const int64_t sideC = inner + 2 * mc;
    const std::vector<int64_t> rows = storedRowsFromTop(levelC);
    parallelFor(static_cast<int64_t>(rows.size()), threads, [&](int64_t i) {
        const int64_t row = rows[static_cast<size_t>(i)];
        if (row < mc || row >= sideC - mc) {
            bandInto(levelC, c, row, 0, sideC);
        } else {
            bandInto(levelC, c, row, 0, mc);
            bandInto(levelC, c, row, mc + inner, sideC);
        }
    });
}

void OrthoLevels::Impl::blankSubtree(int l, int tx, int ty, TileBatch& out) const {
    out.push_back(blankTile(l, tx, ty));
    if (l < M) {
        for (int c = 0; c < 4; ++c) {
            blankSubtree(l + 1, 2 * tx + (c & 1), 2 * ty + (c >> 1), out);
        }
    }
}

int OrthoLevels::topLevels(WalkOrder order) const {
    const Impl& m = *impl_;
    return order == WalkOrder::SinglePass && m.M > 0 ? m.singlePassC : m.C;
}

int64_t OrthoLevels::subtreeItems(WalkOrder order, bool pruned) const {
    const Impl& m = *impl_;
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
    return m.C == m.M || subtreeItems(WalkOrder::CoarseFirst, true) == subtreeItems(WalkOrder::CoarseFirst);
}

bool OrthoLevels::isFace() const {
    return impl_->margin(0) > 0;
}

int64_t OrthoLevels::itemWindow() const {
    return std::max<int64_t>(4, 2 * impl_->threads);
}

int64_t OrthoLevels::walk(const Sink& sink, WalkOrder order, const Range* range, bool pruned) const {
    const Impl& m = *impl_;
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
        const bool whole = begin == 0 && end == items && (!range || range->top);
        const BlockMask reach = m.reachOf(c);
        std::vector<SparseLevel> levels(static_cast<size_t>(c) + 1);
        SparseLevel& levelC = levels[static_cast<size_t>(c)];
        if (whole) {
            levelC = SparseLevel(m.sideWithMargin(c), m.channels, reach);
        }
        if (!m.handSubtrees(sink, c + 1, begin, end, 0, false, reach, whole ? &levelC : nullptr, list) ||
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
