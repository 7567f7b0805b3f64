// Inputs of several resolutions (ortho_levels.hpp, "Several resolutions"): which tiles hold
// resolution of their own, the pixels of a level by the rule of several resolutions, levels 0..C
// and the subtrees walked where the input's parts need them.
#include "libpyramid/encode/ortho/ortho_levels_impl.hpp"

#include <algorithm>

#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

int64_t floorDiv(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

uint64_t tileKey(int l, int64_t tx, int64_t ty) {
    return (static_cast<uint64_t>(l) << 58) | (static_cast<uint64_t>(tx) << 29) | static_cast<uint64_t>(ty);
}

// Pixels [x, x + w) x [y, y + h) of `img`, whose pixel (0, 0) is (ox, oy).
Image8 crop(const Image8& img, int64_t ox, int64_t oy, int64_t x, int64_t y, int w, int h) {
    Image8 out(w, h, img.channels, Image8::Unset);
    const size_t rowBytes = static_cast<size_t>(w) * static_cast<size_t>(img.channels);
    for (int j = 0; j < h; ++j) {
        std::copy_n(img.at(static_cast<int>(x - ox), static_cast<int>(y - oy + j)), rowBytes, out.at(0, j));
    }
    return out;
}

// Writes `part` into `img` (pixel (0, 0) at (ox, oy)) with its pixel (0, 0) at (x, y).
void paste(Image8& img, int64_t ox, int64_t oy, const Image8& part, int64_t x, int64_t y) {
    const size_t rowBytes = static_cast<size_t>(part.width) * static_cast<size_t>(part.channels);
    for (int j = 0; j < part.height; ++j) {
        std::copy_n(part.at(0, j), rowBytes, img.at(static_cast<int>(x - ox), static_cast<int>(y - oy + j)));
    }
}

} // namespace

bool OrthoLevels::Impl::reached(int l, int64_t tx, int64_t ty) const {
    if (!several || l == 0) {
        return true;
    }
    if (tx < 0 || ty < 0 || tx >= (int64_t{1} << l) || ty >= (int64_t{1} << l)) {
        return false; // beyond a face: its pixels are sampled at their own level
    }
    const uint64_t key = tileKey(l, tx, ty);
    {
        const std::lock_guard<std::mutex> lock(reachMutex);
        const auto it = reachMemo.find(key);
        if (it != reachMemo.end()) {
            return it->second;
        }
    }
    const int64_t x0 = tx * T, y0 = ty * T;
    const bool r = reached(l - 1, tx / 2, ty / 2) && pixels->mayNeedLevel(levelWidth(l), x0, y0, x0 + T - 1, y0 + T - 1);
    const std::lock_guard<std::mutex> lock(reachMutex);
    reachMemo.emplace(key, r);
    return r;
}

const std::vector<uint64_t>& OrthoLevels::Impl::reachedAt(int l) const {
    {
        const std::lock_guard<std::mutex> lock(reachMutex);
        const auto it = reachedLists.find(l);
        if (it != reachedLists.end()) {
            return it->second;
        }
    }
    std::vector<uint64_t> tiles;
    if (l == 0) {
        tiles.push_back(0);
    } else {
        // The children of the reached tiles of level l - 1, in Z order, asked in parallel.
        const std::vector<uint64_t>& parents = reachedAt(l - 1);
        std::vector<uint8_t> keep(4 * parents.size());
        parallelFor(static_cast<int64_t>(keep.size()), threads, [&](int64_t i) {
            const auto [tx, ty] = mortonDecode(4 * parents[static_cast<size_t>(i / 4)] + static_cast<uint64_t>(i % 4));
            keep[static_cast<size_t>(i)] = reached(l, tx, ty) ? 1 : 0;
        });
        for (size_t i = 0; i < keep.size(); ++i) {
            if (keep[i]) {
                tiles.push_back(4 * parents[i / 4] + (i % 4));
            }
        }
    }
    const std::lock_guard<std::mutex> lock(reachMutex);
    return reachedLists.emplace(l, std::move(tiles)).first->second;
}

TrueTile OrthoLevels::Impl::beyondTile(int l, int tx, int ty) const {
    TrueTile t = blankTile(l, tx, ty);
    t.blankBelow = true;
    t.beyond = true;
    return t;
}

// Level-l pixels [x0, x0 + w) x [y0, y0 + h): under each level-(l+1) tile that holds
// resolution, the 2x2 averages of `finer(x, y, w, h)` (level-(l+1) pixels); elsewhere the input
// sampled at their own centres. The finest level is sampled.
Image8 OrthoLevels::Impl::severalBox(int l, int64_t x0, int64_t y0, int w, int h, const Finer& finer) const {
    if (l == M) {
        return pixels->sampleAt(levelWidth(l), x0, y0, w, h);
    }
    const int64_t half = T / 2; // a level-(l+1) tile's width at level l
    const int64_t kx0 = floorDiv(x0, half), kx1 = floorDiv(x0 + w - 1, half);
    const int64_t ky0 = floorDiv(y0, half), ky1 = floorDiv(y0 + h - 1, half);
    bool any = false, all = true;
    for (int64_t ky = ky0; ky <= ky1; ++ky) {
        for (int64_t kx = kx0; kx <= kx1; ++kx) {
            const bool r = reached(l + 1, kx, ky);
            any = any || r;
            all = all && r;
        }
    }
    if (!any) {
        return pixels->sampleAt(levelWidth(l), x0, y0, w, h);
    }
    if (all) {
        return averager.reduce(finer(2 * x0, 2 * y0, 2 * w, 2 * h));
    }
    Image8 out(w, h, channels, Image8::Unset); // every pixel lies under one of the tiles
    for (int64_t ky = ky0; ky <= ky1; ++ky) {
        for (int64_t kx = kx0; kx <= kx1; ++kx) {
            const int64_t rx0 = std::max(x0, kx * half), rx1 = std::min(x0 + w, (kx + 1) * half);
            const int64_t ry0 = std::max(y0, ky * half), ry1 = std::min(y0 + h, (ky + 1) * half);
            const int rw = static_cast<int>(rx1 - rx0), rh = static_cast<int>(ry1 - ry0);
            paste(out, x0, y0,
                  reached(l + 1, kx, ky) ? averager.reduce(finer(2 * rx0, 2 * ry0, 2 * rw, 2 * rh))
                                         : pixels->sampleAt(levelWidth(l), rx0, ry0, rw, rh),
                  rx0, ry0);
        }
    }
    return out;
}

Image8 OrthoLevels::Impl::severalDeep(int l, int64_t x0, int64_t y0, int w, int h) const {
    return severalBox(l, x0, y0, w, h,
                      [&](int64_t x, int64_t y, int fw, int fh) { return severalDeep(l + 1, x, y, fw, fh); });
}

// The blocks of level l (a face's margin from 0) that meet a tile holding resolution or its
// border: those the level stores.
BlockMask OrthoLevels::Impl::severalMask(int l) const {
    const int64_t side = sideWithMargin(l), m = margin(l), width = levelWidth(l);
    BlockMask mask(side, 0);
    for (const uint64_t code : reachedAt(l)) {
        const auto [tx, ty] = mortonDecode(code);
        const auto px = [&](int64_t p) { return std::clamp<int64_t>(pixels->borderPixel(p, width) + m, 0, side - 1); };
        const int64_t x0 = px(int64_t{tx} * T - kTileBorder), x1 = px(int64_t{tx + 1} * T + kTileBorder - 1);
        const int64_t y0 = px(int64_t{ty} * T - kTileBorder), y1 = px(int64_t{ty + 1} * T + kTileBorder - 1);
        for (int64_t by = y0 / kSparseBlock; by <= y1 / kSparseBlock; ++by) {
            for (int64_t bx = x0 / kSparseBlock; bx <= x1 / kSparseBlock; ++bx) {
                mask.store(bx, by);
            }
        }
    }
    mask.seal();
    return mask;
}

// Levels 0..c, each block stored by severalMask, finest first: level c by severalDeep, each
// coarser one from the level below it.
std::vector<SparseLevel> OrthoLevels::Impl::severalCoarseLevels(int c) const {
    std::vector<SparseLevel> levels(static_cast<size_t>(c) + 1);
    for (int l = c; l >= 0; --l) {
        SparseLevel& level = levels[static_cast<size_t>(l)];
        level = SparseLevel(sideWithMargin(l), channels, severalMask(l));
        const SparseLevel* below = l < c ? &levels[static_cast<size_t>(l) + 1] : nullptr;
        const int64_t m = margin(l), side = level.side();
        const int64_t mBelow = below ? margin(l + 1) : 0;
        const Finer fromBelow = [&](int64_t x, int64_t y, int w, int h) {
            Image8 img(w, h, channels, Image8::Unset);
            for (int j = 0; j < h; ++j) {
                below->read(x + mBelow, y + j + mBelow, w, img.at(0, j));
            }
            return img;
        };
        const Finer deep = [&](int64_t x, int64_t y, int w, int h) { return severalDeep(l + 1, x, y, w, h); };
        parallelFor(level.mask().count(), threads, [&](int64_t k) {
            const auto [bx, by] = level.mask().block(k);
            const int64_t x0 = bx * kSparseBlock, y0 = by * kSparseBlock;
            const int w = static_cast<int>(std::min(side, x0 + kSparseBlock) - x0);
            const int h = static_cast<int>(std::min(side, y0 + kSparseBlock) - y0);
            level.write(severalBox(l, x0 - m, y0 - m, w, h, below ? fromBelow : deep), x0, y0);
        });
    }
    return levels;
}

// The items of a walk: the children of level c's tiles that hold resolution, in Z order or row
// by row from the north edge, west to east.
OrthoLevels::Impl::ItemList OrthoLevels::Impl::severalItems(int c, bool zOrder) const {
    ItemList items;
    for (const uint64_t code : reachedAt(c)) {
        const auto [tx, ty] = mortonDecode(code);
        for (int k = 0; k < 4; ++k) {
            items.emplace_back(2 * static_cast<int>(tx) + (k & 1), 2 * static_cast<int>(ty) + (k >> 1));
        }
    }
    if (!zOrder) {
        std::sort(items.begin(), items.end(), [](const auto& a, const auto& b) {
            return a.second != b.second ? a.second > b.second : a.first < b.first;
        });
    }
    return items;
}

// The subtree of tile (top, tx, ty): its tiles that hold resolution, each with those below it
// that do, in pre-order; a tile that does not comes alone, as the root of nothing (beyond).
// Each level's pixels are computed over the footprint where a tile holding resolution (or its
// border) is, from the level below.
void OrthoLevels::Impl::severalSubtree(int top, int tx, int ty, TileBatch& out) const {
    if (!reached(top, tx, ty)) {
        out.push_back(beyondTile(top, tx, ty));
        return;
    }
    const int d = M - top;
    const int64_t lo = -margin(top), hi = levelWidth(top) + margin(top);
    const int64_t x0 = std::max<int64_t>(lo, int64_t{tx} * T - kTileBorder);
    const int64_t y0 = std::max<int64_t>(lo, int64_t{ty} * T - kTileBorder);
    const int64_t x1 = std::min<int64_t>(hi, (int64_t{tx} + 1) * T + kTileBorder);
    const int64_t y1 = std::min<int64_t>(hi, (int64_t{ty} + 1) * T + kTileBorder);
    std::vector<Image8> imgs(static_cast<size_t>(d) + 1);
    std::vector<int64_t> ox(imgs.size()), oy(imgs.size());
    for (int j = d; j >= 0; --j) {
        const int l = top + j;
        const int64_t bx0 = x0 << j, by0 = y0 << j, bx1 = x1 << j, by1 = y1 << j;
        ox[static_cast<size_t>(j)] = bx0;
        oy[static_cast<size_t>(j)] = by0;
        Image8& img = imgs[static_cast<size_t>(j)];
        img = Image8(static_cast<int>(bx1 - bx0), static_cast<int>(by1 - by0), channels);
        const Finer finer = [&](int64_t x, int64_t y, int w, int h) {
            return crop(imgs[static_cast<size_t>(j) + 1], ox[static_cast<size_t>(j) + 1], oy[static_cast<size_t>(j) + 1],
                        x, y, w, h);
        };
        const int64_t last = (int64_t{1} << l) - 1;
        for (int64_t ky = std::max<int64_t>(0, floorDiv(by0, T)); ky <= std::min(last, floorDiv(by1 - 1, T)); ++ky) {
            for (int64_t kx = std::max<int64_t>(0, floorDiv(bx0, T)); kx <= std::min(last, floorDiv(bx1 - 1, T)); ++kx) {
                if (!reached(l, kx, ky)) {
                    continue;
                }
                const int64_t rx0 = std::max(bx0, kx * T - kTileBorder), rx1 = std::min(bx1, (kx + 1) * T + kTileBorder);
                const int64_t ry0 = std::max(by0, ky * T - kTileBorder), ry1 = std::min(by1, (ky + 1) * T + kTileBorder);
                paste(img, bx0, by0,
                      severalBox(l, rx0, ry0, static_cast<int>(rx1 - rx0), static_cast<int>(ry1 - ry0), finer), rx0, ry0);
            }
        }
    }
    subtree(top, top, tx, ty, imgs, ox, oy, out);
}

} // namespace pyramid
