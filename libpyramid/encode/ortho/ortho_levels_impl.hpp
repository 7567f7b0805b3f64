// The inside of OrthoLevels (ortho_levels.hpp), shared by its three files: ortho_levels.cpp
// (settings, the walk's orders), ortho_levels_coarse.cpp (levels 0..C held whole, from bands of the
// input) and ortho_levels_items.cpp (the items handed to the sink: levels, subtrees, pruned lists).
#pragma once
#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <utility>
#include <vector>

#include "libpyramid/encode/ortho/ortho_levels.hpp"
#include "libpyramid/encode/ortho/pixel_source.hpp"
#include "libpyramid/encode/ortho/sparse_level.hpp"

namespace pyramid {

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
    void initPlanar(const OrthoLevelsOptions& o);

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
    // those it lists. With `passRows` (row by row, every item, the input's last reader), the
    // input is told the rows the items sampled so far have passed (PixelSource::passedNorthOf).
    using ItemList = std::vector<std::pair<int, int>>;
    bool handSubtrees(const Sink& sink, int top, int64_t begin, int64_t end, int64_t index0, bool zOrder,
                      const BlockMask& reachC, SparseLevel* levelC, const ItemList* items,
                      bool passRows = false) const;
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

    // Inputs of several resolutions (ortho_levels_several.cpp): `several` when the pixel source's
    // parts differ in resolution (PixelSource::severalLevels).
    bool several = false;
    // Whether tile (l, tx, ty) holds resolution of its own: level 0, or its parent does and a part
    // that needs level l may reach its interior (PixelSource::mayNeedLevel). Always, with one
    // resolution. Thread-safe; each tile is asked of the pixel source once.
    bool reached(int l, int64_t tx, int64_t ty) const;
    // The tiles of level l that hold resolution, as Morton codes in Z order (computed once).
    const std::vector<uint64_t>& reachedAt(int l) const;
    TrueTile beyondTile(int l, int tx, int ty) const;
    using Finer = std::function<Image8(int64_t x, int64_t y, int w, int h)>;
    Image8 severalBox(int l, int64_t x0, int64_t y0, int w, int h, const Finer& finer) const;
    Image8 severalDeep(int l, int64_t x0, int64_t y0, int w, int h) const;
    BlockMask severalMask(int l) const;
    std::vector<SparseLevel> severalCoarseLevels(int c) const;
    ItemList severalItems(int c, bool zOrder) const;
    void severalSubtree(int top, int tx, int ty, TileBatch& out) const;
    mutable std::mutex reachMutex;
    mutable std::unordered_map<uint64_t, bool> reachMemo;
    mutable std::map<int, std::vector<uint64_t>> reachedLists;

    void subtree(int top, int l, int tx, int ty, const std::vector<Image8>& imgs, const std::vector<int64_t>& ox,
                 const std::vector<int64_t>& oy, TileBatch& out) const {
        if (l > top && !reached(l, tx, ty)) {
            out.push_back(beyondTile(l, tx, ty)); // several resolutions: none of its own here
            return;
        }
        const size_t k = static_cast<size_t>(l - top);
        out.push_back(extract(imgs[k], ox[k], oy[k], l, tx, ty));
        if (l < M) {
            for (int c = 0; c < 4; ++c) {
                subtree(top, l + 1, 2 * tx + (c & 1), 2 * ty + (c >> 1), imgs, ox, oy, out);
            }
        }
    }
};

} // namespace pyramid
