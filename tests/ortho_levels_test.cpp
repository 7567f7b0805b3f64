// OrthoLevels::walk: its two orders give the same tiles, each in the order it promises; the
// conversion of resampled values to 8 bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <mutex>
#include <random>
#include <stdexcept>
#include <utility>
#include <tuple>

#include "libpyramid/encode/ortho/ortho_levels.hpp"
#include "libpyramid/encode/ortho/planar_pixels.hpp"
#include "libpyramid/encode/ortho/sparse_level.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/map_sources.hpp"
#include "tests/support/box_map.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using Key = std::tuple<int, int, int>; // level, tx, ty

// A textured image, row 0 = north; no two neighbouring pixels alike, so a misplaced tile or
// block cannot go unnoticed.
std::vector<uint16_t> texture(int w, int h, int channels, int maxValue) {
    std::vector<uint16_t> v(static_cast<size_t>(w) * h * channels);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < channels; ++c) {
                const double s = 0.5 + 0.4 * std::sin(x / (5.0 + c) + y / 9.0) * std::cos((x - 2 * y) / 11.0);
                v[(static_cast<size_t>(y) * w + x) * channels + c] =
                    static_cast<uint16_t>(std::lround(s * (maxValue - 40)) + (x * 13 + y * 7 + c * 3) % 37);
            }
        }
    }
    return v;
}

struct Walked {
    std::map<Key, std::vector<uint8_t>> tiles;
    std::vector<Key> order;
    std::vector<Key> blank; // the tiles given as blank (TrueTile::blank)
};

Walked walk(const OrthoLevels& levels, OrthoLevels::WalkOrder order) {
    // Subtrees arrive from several threads at once: kept by item number, then read in order.
    std::map<int64_t, TileBatch> items;
    std::mutex mutex;
    OrthoLevels::Sink sink;
    sink.subtree = sink.level = [&](int64_t index, TileBatch& item) {
        std::lock_guard<std::mutex> lock(mutex);
        EXPECT_TRUE(items.emplace(index, std::move(item)).second) << "item " << index << " given twice";
        return true;
    };
    const int64_t count = levels.walk(sink, order);
    EXPECT_EQ(count, static_cast<int64_t>(items.size()));
    Walked w;
    int64_t expected = 0;
    for (const auto& [index, item] : items) {
        EXPECT_EQ(index, expected++) << "the items are numbered 0, 1, 2...";
        for (const TrueTile& t : item) {
            const Key k{t.level, t.tx, t.ty};
            std::vector<uint8_t> pixels(t.image().pixels.begin(), t.image().pixels.end());
            EXPECT_TRUE(w.tiles.emplace(k, std::move(pixels)).second) << "tile given twice";
            w.order.push_back(k);
            if (t.blank) {
                w.blank.push_back(k);
            }
        }
    }
    return w;
}

// Every tile of the pyramid (levels 0..M) is given once.
void expectEveryTile(const Walked& w, int maxLevel) {
    EXPECT_EQ(static_cast<int64_t>(w.tiles.size()), ((int64_t{1} << (2 * (maxLevel + 1))) - 1) / 3);
    for (const auto& [k, pixels] : w.tiles) {
        const auto [l, tx, ty] = k;
        EXPECT_TRUE(l >= 0 && l <= maxLevel && tx >= 0 && ty >= 0 && tx < (1 << l) && ty < (1 << l));
    }
}

// Both orders' promises, and the same tiles.
void expectTheSameTilesInTheirOrders(const OrthoLevels& levels) {
    const int M = levels.maxLevel();
    const Walked coarse = walk(levels, OrthoLevels::WalkOrder::CoarseFirst);
    const Walked single = walk(levels, OrthoLevels::WalkOrder::SinglePass);
    expectEveryTile(coarse, M);
    expectEveryTile(single, M);
    EXPECT_TRUE(coarse.tiles == single.tiles);

    // CoarseFirst: every tile after its parent.
    std::map<Key, size_t> at;
    for (size_t i = 0; i < coarse.order.size(); ++i) {
        at[coarse.order[i]] = i;
    }
    for (const auto& [k, i] : at) {
        const auto [l, tx, ty] = k;
        if (l > 0) {
            EXPECT_LT(at.at(Key{l - 1, tx / 2, ty / 2}), i);
        }
    }
    // SinglePass: the finest tiles come north first (tile rows never go back south), and the
    // root comes after every finest tile.
    int lastRow = 1 << M;
    size_t lastFinest = 0;
    for (size_t i = 0; i < single.order.size(); ++i) {
        const auto [l, tx, ty] = single.order[i];
        if (l == M) {
            const int row = ty >> std::min(M, 3); // the subtrees' rows, 3 levels deep at most
            EXPECT_LE(row, lastRow);
            lastRow = row;
            lastFinest = i;
        }
    }
    if (M > 0) {
        EXPECT_GT(std::find(single.order.begin(), single.order.end(), Key{0, 0, 0}) - single.order.begin(),
                  static_cast<std::ptrdiff_t>(lastFinest));
    }
}

// The geometries of each branch: pixel exact; resampled with the lower part of the square
// beyond a wide input (whole subtrees black); 16-bit; 1 to 4 channels; few and many levels
// (the single pass's deeper level C from 3 levels on).
// The documented conversion of a resampled value to 8 bits, as a reader of doc/ortho-encoding.md
// computes it.
uint8_t documented(double top, double bottom, double fy, double full) {
    const double v = top + (bottom - top) * fy;
    return static_cast<uint8_t>(std::lround(v * 255.0 / full));
}

// combineRows takes 8-bit input without the formula's * 255 / 255: every value within eight
// units in the last place of a half, where the two could round apart, and random rows, give
// the formula's bytes; so do 16-bit rows.
TEST(PlanarPixels, EightBitsAsTheDocumentedRounding) {
    std::vector<double> values;
    for (int k = 0; k < 255; ++k) {
        double v = k + 0.5;
        for (int j = 0; j < 8; ++j) {
            v = std::nextafter(v, 0.0);
        }
        for (int j = -8; j <= 8; ++j, v = std::nextafter(v, 256.0)) {
            values.push_back(v);
        }
    }
    values.push_back(0.0);
    values.push_back(255.0);
    std::vector<double> zeros(values.size(), 0.0);
    std::vector<uint8_t> row(values.size());
    combineRows(values.data(), zeros.data(), 0.0, 255.0, values.size(), row.data()); // v = top
    for (size_t k = 0; k < values.size(); ++k) {
        ASSERT_EQ(row[k], documented(values[k], 0.0, 0.0, 255.0)) << std::hexfloat << values[k];
    }
    int differ = 0; // random values whose two forms differ before rounding (about 1 in 250)
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> sample(0.0, 255.0), weight(0.0, 1.0);
    for (const double full : {255.0, 65535.0}) {
        const size_t n = 4099; // not a multiple of any vector's width
        std::vector<double> top(n), bottom(n);
        for (size_t k = 0; k < n; ++k) {
            top[k] = sample(random) * full / 255.0;
            bottom[k] = sample(random) * full / 255.0;
        }
        for (int r = 0; r < 20; ++r) {
            const double fy = weight(random);
            std::vector<uint8_t> out(n);
            combineRows(top.data(), bottom.data(), fy, full, n, out.data());
            for (size_t k = 0; k < n; ++k) {
                ASSERT_EQ(out[k], documented(top[k], bottom[k], fy, full)) << full << " " << k;
                const double v = top[k] + (bottom[k] - top[k]) * fy;
                differ += full == 255.0 && v * 255.0 / 255.0 != v;
            }
        }
    }
    EXPECT_GT(differ, 50);
}

// An 8-bit input as wide as the finest level and less high is read into place (sampleWide); the
// same image in 16 bits (each value v as v * 257, which converts back to v) takes the bilinear
// path: the same pixels, and 0 below the input.
TEST(PlanarPixels, WideInputsAtScaleOneAreTheirPixels) {
    test::TempDir dir;
    const int width = 64, height = 23;
    const std::vector<uint16_t> eight = texture(width, height, 3, 255);
    std::vector<uint16_t> sixteen(eight.size());
    std::transform(eight.begin(), eight.end(), sixteen.begin(), [](uint16_t v) { return static_cast<uint16_t>(v * 257); });
    test::writeImage(dir.file("wide8.png"), width, height, 3, eight, false);
    test::writeImage(dir.file("wide16.png"), width, height, 3, sixteen, true);
    const auto source8 = RasterSource::open(dir.file("wide8.png"));
    const auto source16 = RasterSource::open(dir.file("wide16.png"));
    const PlanarPixels pixels8(*source8, 3, width, false), pixels16(*source16, 3, width, false);
    int inside = 0;
    for (const auto& [x0, y0, w, h] : {std::tuple{0, 0, 64, 64}, std::tuple{5, 30, 20, 20}, std::tuple{0, 41, 64, 23},
                                       std::tuple{10, 40, 7, 1}, std::tuple{3, 0, 9, 40}, std::tuple{0, 63, 64, 1}}) {
        const Image8 a = pixels8.sample(x0, y0, w, h), b = pixels16.sample(x0, y0, w, h);
        ASSERT_EQ(a.pixels, b.pixels) << x0 << "," << y0 << " " << w << "x" << h;
        for (int j = 0; j < h; ++j) {
            const int row = width - 1 - (y0 + j); // the input row, from the north
            for (int i = 0; i < w; ++i) {
                for (int c = 0; c < 3; ++c) {
                    const uint16_t want = row < height ? eight[(static_cast<size_t>(row) * width + x0 + i) * 3 + c] : 0;
                    ASSERT_EQ(a.at(i, j)[c], want) << i << "," << j;
                    inside += row < height;
                }
            }
        }
    }
    EXPECT_GT(inside, 3 * 64 * 23);
}

TEST(OrthoLevels, BothOrdersGiveTheSameTiles) {
    struct Case {
        int w, h, channels, tileSize;
        bool sixteen;
        int threads;
    };
    for (const Case& c : {Case{64, 64, 3, 16, false, 2}, Case{64, 64, 3, 4, false, 1}, Case{200, 60, 3, 8, false, 2},
                          Case{200, 60, 4, 8, true, 2}, Case{90, 120, 1, 6, false, 2}, Case{37, 50, 2, 4, true, 1}}) {
        SCOPED_TRACE(std::to_string(c.w) + "x" + std::to_string(c.h) + "x" + std::to_string(c.channels) + " tiles of " +
                     std::to_string(c.tileSize) + (c.sixteen ? ", 16 bits" : ""));
        test::TempDir dir;
        test::writeImage(dir.file("in.png"), c.w, c.h, c.channels,
                         texture(c.w, c.h, c.channels, c.sixteen ? 65535 : 255), c.sixteen);
        OrthoLevelsOptions o;
        o.tileSize = c.tileSize;
        o.threads = c.threads;
        expectTheSameTilesInTheirOrders(OrthoLevels(dir.file("in.png"), o));
    }
}

// Cube faces: the single pass assembles level C from the subtrees and its margin beyond the
// face from bands; the margin's pixels reach every tile border of levels 0..C, so any slip
// shows as a tile that differs from the coarse-first walk's. Faces 1 (pole) and 3 (equator),
// a whole-globe and a partial map (0 beyond it), few and many levels.
TEST(OrthoLevels, BothOrdersGiveTheSameFaceTiles) {
    test::TempDir dir;
    test::writeImage(dir.file("globe.png"), 96, 48, 3, texture(96, 48, 3, 255), false);
    const auto source = RasterSource::open(dir.file("globe.png"));
    const PlanetBody body = PlanetBody::parse("wgs84");
    for (const char* extent : {"-180,-90,180,90", "-40,-30,50,60"}) {
        for (const int face : {1, 3}) {
            for (const int maxLevel : {2, 4}) {
                SCOPED_TRACE(std::string(extent) + " face " + std::to_string(face) + " maxLevel " +
                             std::to_string(maxLevel));
                OrthoLevelsOptions o;
                o.tileSize = 4;
                o.maxLevel = maxLevel;
                o.threads = 2;
                expectTheSameTilesInTheirOrders(OrthoLevels(*source, GeoExtent::parse(extent), body, face, o));
            }
        }
    }
}

// The levels held whole (0..C) keep only the blocks a map may reach (sparse_level.hpp): a face
// that a small map barely touches gives, in both orders, the tiles of the same map saying that
// it may have values anywhere, those of levels 0..C that no stored block meets as blank tiles
// (tiles away from the map; none when the map may be anywhere).
TEST(OrthoLevels, LevelsHeldWholeAreBlankWhereTheMapCannotReach) {
    const PlanetBody body = PlanetBody::parse("wgs84");
    std::map<bool, std::map<OrthoLevels::WalkOrder, Walked>> walks;
    for (const bool everywhere : {true, false}) {
        std::atomic<int64_t> points{0};
        const MapSources sources =
            globalMapSources("box", std::make_unique<test::BoxMap>(GeoExtent::parse("40,10,55,30"), everywhere, points), 3,
                             1024, SampleType::UInt8);
        OrthoLevelsOptions o;
        o.tileSize = 16;
        o.maxLevel = 7; // level C 3 blocks across (coarse first), 10 (single pass)
        o.threads = 2;
        const OrthoLevels levels(*sources.source, sources.placement, body, 3, o, sources.map.get());
        for (const auto order : {OrthoLevels::WalkOrder::CoarseFirst, OrthoLevels::WalkOrder::SinglePass}) {
            SCOPED_TRACE(std::string(everywhere ? "everywhere" : "box") +
                         (order == OrthoLevels::WalkOrder::CoarseFirst ? ", coarse first" : ", single pass"));
            Walked w = walk(levels, order);
            const int top = levels.topLevels(order);
            ASSERT_GE(top, 3);
            int64_t blankTop = 0;
            for (const Key& k : w.blank) {
                const auto& pixels = w.tiles.at(k);
                EXPECT_TRUE(std::all_of(pixels.begin(), pixels.end(), [](uint8_t v) { return v == 0; }));
                blankTop += std::get<0>(k) <= top;
            }
            if (everywhere) {
                EXPECT_TRUE(w.blank.empty());
            } else {
                // Level `top` has 4^top tiles; the box covers a corner of a few of them.
                EXPECT_GT(blankTop, (int64_t{1} << (2 * top)) / 2);
            }
            walks[everywhere][order] = std::move(w);
        }
    }
    for (const auto order : {OrthoLevels::WalkOrder::CoarseFirst, OrthoLevels::WalkOrder::SinglePass}) {
        EXPECT_TRUE(walks[false][order].tiles == walks[true][order].tiles);
    }
    EXPECT_TRUE(walks[false][OrthoLevels::WalkOrder::CoarseFirst].tiles ==
                walks[false][OrthoLevels::WalkOrder::SinglePass].tiles);
}

// Beyond a wide input the square's lower part is black and transparent at every level, and
// tiles straddling the input's edge are not.
TEST(OrthoLevels, BeyondTheInputTilesAreBlack) {
    test::TempDir dir;
    const int w = 200, h = 60;
    test::writeImage(dir.file("in.png"), w, h, 4, texture(w, h, 4, 255), false);
    OrthoLevelsOptions o;
    o.tileSize = 8;
    const OrthoLevels levels(dir.file("in.png"), o);
    ASSERT_EQ(levels.maxLevel(), 5); // 256 pixels across, the input's 60 rows over the top 77
    const Walked single = walk(levels, OrthoLevels::WalkOrder::SinglePass);
    const int W = 256;
    const double covered = h * (W / static_cast<double>(w)); // finest rows holding the input
    for (const auto& [k, pixels] : single.tiles) {
        const auto [l, tx, ty] = k;
        // The tile's rows with their border, in finest rows from the south.
        const double top = ((ty + 1) * 8 + 2) << (5 - l);
        const double bottom = (ty * 8 - 2) * (1 << (5 - l));
        const bool black = std::all_of(pixels.begin(), pixels.end(), [](uint8_t v) { return v == 0; });
        if (top <= W - covered - 1) {
            EXPECT_TRUE(black) << "tile " << l << "," << tx << "," << ty;
        } else if (bottom >= W - covered + 1) {
            EXPECT_FALSE(black) << "tile " << l << "," << tx << "," << ty;
        }
    }
}

// A level stored in blocks: reducing it is reducing the whole image (0 where no block is stored),
// block by block, and it reads back what was written, 0 elsewhere. A level 2.5 blocks across
// and odd block counts check the far edges; colour written where no block is stored is refused.
TEST(SparseLevel, ReducesAndReadsAsTheWholeImage) {
    constexpr int64_t B = kSparseBlock;
    const int64_t side = 5 * B / 2 * 2; // 5 blocks across; the reduced level 2.5
    const int channels = 3;
    const int64_t across = SparseLevel::blocks(side);
    ASSERT_EQ(across, 5);
    std::mt19937 random(7);
    BlockMask mask(side, 0);
    std::vector<uint8_t> stored(static_cast<size_t>(across * across));
    for (size_t k = 0; k < stored.size(); ++k) {
        stored[k] = k == 0 || k + 1 == stored.size() || random() % 3 == 0 ? 1 : 0;
        if (stored[k]) {
            mask.store(static_cast<int64_t>(k) % across, static_cast<int64_t>(k) / across);
        }
    }
    SparseLevel level(side, channels, mask);
    Image8 dense(static_cast<int>(side), static_cast<int>(side), channels);
    for (int64_t y = 0; y < side; ++y) {
        for (int64_t x = 0; x < side; ++x) {
            if (!level.stored(x / B, y / B)) {
                continue;
            }
            for (int c = 0; c < channels; ++c) {
                dense.at(static_cast<int>(x), static_cast<int>(y))[c] = static_cast<uint8_t>(1 + random() % 255);
            }
        }
    }
    // Written in rows of uneven pieces that cross blocks, stored or not.
    for (int64_t y = 0; y < side; ++y) {
        for (int64_t x = 0; x < side;) {
            const int64_t n = std::min<int64_t>(side - x, 1 + static_cast<int64_t>(random() % (2 * B)));
            Image8 piece(static_cast<int>(n), 1, channels);
            std::copy_n(dense.at(static_cast<int>(x), static_cast<int>(y)), n * channels, piece.at(0, 0));
            level.write(piece, x, y);
            x += n;
        }
    }
    const ColourAverager averager(ColourSpace::Srgb, channels);
    const Image8 half = averager.reduce(dense);
    const SparseLevel reduced = level.reduced(averager, 2);
    ASSERT_EQ(reduced.side(), side / 2);
    for (const auto& [lvl, want] : {std::pair<const SparseLevel*, const Image8*>{&level, &dense}, {&reduced, &half}}) {
        std::vector<uint8_t> row(static_cast<size_t>(lvl->side()) * channels);
        for (int64_t y = 0; y < lvl->side(); ++y) {
            lvl->read(0, y, lvl->side(), row.data());
            ASSERT_TRUE(std::equal(row.begin(), row.end(), want->at(0, static_cast<int>(y)))) << "row " << y;
        }
    }
    EXPECT_FALSE(reduced.blank(0, 0, 0, 0));
    // A block of four unstored blocks stays unstored, and reads 0.
    for (int64_t by = 0; by < SparseLevel::blocks(reduced.side()); ++by) {
        for (int64_t bx = 0; bx < SparseLevel::blocks(reduced.side()); ++bx) {
            bool any = false;
            for (int q = 0; q < 4; ++q) {
                any = any || level.stored(2 * bx + (q & 1), 2 * by + (q >> 1));
            }
            EXPECT_EQ(reduced.stored(bx, by), any) << bx << "," << by;
            EXPECT_EQ(reduced.blank(bx * B, by * B, bx * B + B - 1, by * B + B - 1), !any);
        }
    }
    const auto unstored = std::find(stored.begin(), stored.end(), uint8_t{0});
    ASSERT_NE(unstored, stored.end());
    const int64_t b = unstored - stored.begin();
    Image8 colour(2, 1, channels);
    colour.at(1, 0)[2] = 9;
    EXPECT_THROW(level.write(colour, (b % across) * B, (b / across) * B), std::logic_error);
    EXPECT_NO_THROW(level.write(Image8(2, 1, channels), (b % across) * B, (b / across) * B));
}

} // namespace
} // namespace pyramid
