#include "libpyramid/encode/ortho/ortho_levels_impl.hpp"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <tuple>

#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

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
            if (!reached(l, tx, ty)) {
                t = beyondTile(l, static_cast<int>(tx), static_cast<int>(ty));
                return;
            }
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
    if (several) {
        return severalItems(c, zOrder);
    }
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
                                     const ItemList* items, bool passRows) const {
    const int side = 1 << top;
    std::atomic<bool> stop{false};
    // Items are sampled out of order by the threads; the rows passed are those north of the
    // first item not yet sampled (row by row from the north: no later item reaches higher).
    std::mutex passMutex;
    std::vector<char> sampled(passRows ? static_cast<size_t>(end - begin) : 0);
    int64_t unsampled = 0;
    const auto passed = [&](int64_t i) {
        int64_t north = -1; // every item sampled: every row passed
        {
            const std::lock_guard<std::mutex> lock(passMutex);
            sampled[static_cast<size_t>(i)] = 1;
            while (unsampled < end - begin && sampled[static_cast<size_t>(unsampled)]) {
                ++unsampled;
            }
            if (unsampled < end - begin) {
                const int64_t ty = side - 1 - (begin + unsampled) / side;
                const int64_t y1 = std::min<int64_t>(levelWidth(top) + margin(top), (ty + 1) * T + kTileBorder);
                north = (y1 << (M - top)) - 1;
            }
        }
        pixels->passedNorthOf(north);
    };
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
            if (passRows) {
                passed(i);
            }
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
    if (several) {
        severalSubtree(top, tx, ty, out);
        return;
    }
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

void OrthoLevels::Impl::blankSubtree(int l, int tx, int ty, TileBatch& out) const {
    out.push_back(blankTile(l, tx, ty));
    if (l < M) {
        for (int c = 0; c < 4; ++c) {
            blankSubtree(l + 1, 2 * tx + (c & 1), 2 * ty + (c >> 1), out);
        }
    }
}

} // namespace pyramid
