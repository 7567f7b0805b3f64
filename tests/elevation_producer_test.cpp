// The CPU residual and elevation producers on the original tools' DEM.dat: root values from
// the decoded residuals, the upsample-and-add by hand, and bit-for-bit agreement between all
// elevation tile sizes (each with its own delta) wherever their samples coincide.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <thread>

#include "formats/error.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/level_heights.hpp"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

std::string demPath() { return test::dataPath("proland/DEM.dat"); }

std::shared_ptr<ElevationProducer> makeProducer(int n, size_t capacity = 64, const std::string& path = demPath()) {
    auto header = ResidualFileReader::open(path)->header();
    ResidualProducerOptions ro;
    ro.delta = elevationDelta(header, n);
    auto residuals = std::make_shared<ResidualProducer>(path, std::vector<std::string>{}, ro);
    ElevationProducerOptions eo;
    eo.tileSize = n;
    eo.cacheCapacity = capacity;
    return std::make_shared<ElevationProducer>(residuals, eo);
}

TEST(ElevationProducer, DeltaFollowsTileSize) {
    auto h = ResidualFileReader::open(demPath())->header();
    EXPECT_EQ(elevationDelta(h, 192), 3);
    EXPECT_EQ(elevationDelta(h, 96), 2);
    EXPECT_EQ(elevationDelta(h, 48), 1);
    EXPECT_EQ(elevationDelta(h, 24), 0);
    EXPECT_THROW(elevationDelta(h, 12), Error); // would need delta -1
    EXPECT_THROW(elevationDelta(h, 100), Error);
}

TEST(ElevationProducer, RootIsScaledResidual) {
    auto producer = makeProducer(24);
    auto root = producer->tile(0, 0, 0);
    ASSERT_EQ(root->size, 29);
    auto r = ResidualFileReader::open(demPath())->readTile(0, 0, 0);
    for (size_t k = 0; k < r.size(); ++k) {
        ASSERT_EQ(root->zf[k], static_cast<float>(r[k]) * 0.1f);
    }
    EXPECT_EQ(root->zf[0], 1400.0f * 0.1f);
    EXPECT_EQ(root->zf[14 + 14 * 29], 1470.0f * 0.1f);
}

TEST(ElevationProducer, LevelOneIsUpsamplePlusResidual) {
    auto producer = makeProducer(24);
    auto root = producer->tile(0, 0, 0);
    auto child = producer->tile(1, 1, 0);
    auto reader = ResidualFileReader::open(demPath());
    auto r1 = reader->readTile(1, 0, 0); // 53x53: the whole level 1
    const int side = 29;
    // Child sample (3, 2): odd i, even j -> horizontal filter on parent row 2/2+1 = 2, columns
    // around 3/2 + px with px = 1 + 24/2 = 13.
    const float* row = &root->zf[2 * side];
    const float u = ((row[14] + row[15]) * 9.0f - (row[13] + row[16])) / 16.0f;
    const float residual = static_cast<float>(r1[(24 + 3) + 2 * 53]) * 0.1f;
    EXPECT_EQ(child->zf[3 + 2 * side], u + residual);
    // Even-even sample copies the parent.
    EXPECT_EQ(child->zf[4 + 4 * side], root->zf[(2 + 13) + (2 + 1) * side] + static_cast<float>(r1[(24 + 4) + 4 * 53]) * 0.1f);
}

// Every elevation tile size sees the same terrain: same bits at the same file-level sample.
TEST(ElevationProducer, AllTileSizesAgreeBitForBit) {
    const int maxFileLevel = 5;
    std::vector<std::vector<float>> levels(maxFileLevel + 1);
    std::vector<int> sides(maxFileLevel + 1);
    for (int f = 0; f <= maxFileLevel; ++f) {
        sides[f] = (24 << f) + 5;
        levels[f].assign(static_cast<size_t>(sides[f]) * sides[f], std::numeric_limits<float>::quiet_NaN());
    }
    int compared = 0;
    for (int n : {192, 96, 48, 24}) {
        auto producer = makeProducer(n, 8);
        const int delta = n == 192 ? 3 : n == 96 ? 2 : n == 48 ? 1 : 0; // minLevel - log2(192 / n)
        for (int L = 0; L + delta <= maxFileLevel; ++L) {
            const int f = L + delta;
            for (int ty = 0; ty < (1 << L); ++ty) {
                for (int tx = 0; tx < (1 << L); ++tx) {
                    auto t = producer->tile(L, tx, ty);
                    for (int j = 0; j < n + 5; ++j) {
                        for (int i = 0; i < n + 5; ++i) {
                            const size_t g = static_cast<size_t>(tx * n + i) + static_cast<size_t>(ty * n + j) * sides[f];
                            const float v = t->zf[static_cast<size_t>(i + j * (n + 5))];
                            float& seen = levels[f][g];
                            if (std::isnan(seen)) {
                                seen = v;
                            } else {
                                ASSERT_EQ(std::memcmp(&seen, &v, sizeof v), 0)
                                    << "n=" << n << " tile (" << L << "," << tx << "," << ty << ") sample " << i << ","
                                    << j;
                                ++compared;
                            }
                        }
                    }
                }
            }
        }
    }
    EXPECT_GT(compared, 1000000);
}

TEST(ElevationProducer, CacheStaysBoundedAndThreadsAgree) {
    auto a = makeProducer(48, 4);
    auto b = makeProducer(48, 256);
    std::vector<std::thread> threads;
    std::vector<int> mismatches(2, 0);
    for (int t = 0; t < 2; ++t) {
        threads.emplace_back([&, t] {
            for (int ty = 0; ty < 16; ++ty) {
                for (int tx = 0; tx < 16; ++tx) {
                    if (a->tile(4, tx, ty)->zf != b->tile(4, tx, ty)->zf) {
                        ++mismatches[t];
                    }
                }
            }
        });
    }
    for (auto& th : threads) {
        th.join();
    }
    EXPECT_EQ(mismatches[0] + mismatches[1], 0);
}

// Elevation tiles of 24 samples are 64 windows of one 192-tile, and a thread keeps the residual
// tile it decoded last: two producers asked in turn for the same tiles, over DEM.dat and over a
// copy with every residual negated, must each get their own file's residuals. The copy's heights
// are the negated heights, exactly (rounding to nearest is symmetric).
TEST(ElevationProducer, ProducersInTurnOnOneThreadKeepTheirOwnResiduals) {
    test::TempDir dir;
    const std::string negated = dir.file("negated.dat");
    {
        auto reader = ResidualFileReader::open(demPath());
        const ResidualHeader h = reader->header();
        ResidualFileWriter writer(negated, h);
        for (int level = 0; level <= h.maxLevel; ++level) {
            for (int ty = 0; ty < h.tilesPerSide(level); ++ty) {
                for (int tx = 0; tx < h.tilesPerSide(level); ++tx) {
                    std::vector<int16_t> r = reader->readTile(level, tx, ty);
                    for (int16_t& v : r) {
                        ASSERT_NE(v, -32768);
                        v = static_cast<int16_t>(-v);
                    }
                    writer.writeTile(level, tx, ty, r);
                }
            }
        }
        writer.finish();
        writer.commit();
    }
    auto a = makeProducer(24, 64, demPath());
    auto b = makeProducer(24, 64, negated);
    int tiles = 0;
    for (int level = 0; level <= a->maxLevel(); ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                const auto za = a->tile(level, tx, ty);
                const auto zb = b->tile(level, tx, ty);
                for (size_t s = 0; s < za->zf.size(); ++s) {
                    ASSERT_EQ(zb->zf[s], -za->zf[s]) << "tile " << tileCoordinates(level, tx, ty) << " sample " << s;
                }
                ++tiles;
            }
        }
    }
    EXPECT_EQ(tiles, 1365); // levels 0..5
}

TEST(ElevationProducer, CoarseElevationsInterpolateTheParentMesh) {
    auto producer = makeProducer(24);
    auto parent = producer->tile(1, 0, 0);
    auto child = producer->tile(2, 1, 1);
    const int side = 29;
    // Child interior sample (0,0) sits on a parent mesh vertex: parent sample (12+2, 12+2).
    EXPECT_EQ(child->zc[2 + 2 * side], parent->zm()[14 + 14 * side]);
    // Child sample (1,0) is the midpoint of a parent mesh edge (gridSize = n: cells of 2).
    const float a = parent->zm()[14 + 14 * side], b = parent->zm()[15 + 14 * side];
    EXPECT_EQ(child->zc[3 + 2 * side], 0.5f * a + 0.5f * b);
}

// The rule every height reader shares (level_heights.hpp): cells, clamping and the order of the
// bilinear arithmetic, on a level of 3 x 3 tiles of 4 intervals whose heights are a bilinear
// function of the level's vertex coordinates (exact in double, so every point is exact).
TEST(LevelHeights, CellsClampingAndExactBilinear) {
    const int n = 4, side = n + 5;
    const int64_t across = 3;
    const auto f = [](double x, double y) { return 5.0 + 3.0 * x - 2.0 * y + 0.5 * x * y; };
    std::vector<std::vector<float>> tiles(static_cast<size_t>(across * across));
    for (int ty = 0; ty < across; ++ty) {
        for (int tx = 0; tx < across; ++tx) {
            auto& z = tiles[static_cast<size_t>(ty * across + tx)];
            z.resize(static_cast<size_t>(side * side));
            for (int j = -2; j <= n + 2; ++j) {
                for (int i = -2; i <= n + 2; ++i) {
                    z[static_cast<size_t>((j + 2) * side + i + 2)] = static_cast<float>(f(tx * n + i, ty * n + j));
                }
            }
        }
    }
    const auto height = [&](double x, double y) {
        const LevelCell c = levelCell(n, across, x, y);
        return cellHeight(tiles[static_cast<size_t>(c.ty * across + c.tx)].data(), n, c);
    };
    for (double y = 0.0; y <= 12.0; y += 0.375) {
        for (double x = 0.0; x <= 12.0; x += 0.625) {
            ASSERT_EQ(height(x, y), f(x, y)) << x << "," << y;
        }
    }
    // A vertex on a tile edge belongs to the tile east (north) of it; the east and north edges
    // of the level to the last cells.
    LevelCell c = levelCell(n, across, 4.0, 11.5);
    EXPECT_EQ(c.tx, 1);
    EXPECT_EQ(c.i, 0);
    EXPECT_EQ(c.wx, 0.0);
    EXPECT_EQ(c.ty, 2);
    EXPECT_EQ(c.j, 3);
    EXPECT_EQ(c.wy, 0.5);
    c = levelCell(n, across, 12.0, 12.0);
    EXPECT_EQ(c.tx, 2);
    EXPECT_EQ(c.i, n - 1);
    EXPECT_EQ(c.wx, 1.0);
    EXPECT_EQ(c.ty, 2);
    EXPECT_EQ(c.wy, 1.0);
    // Beyond the level, its edge continues.
    EXPECT_EQ(height(-3.0, 5.25), f(0.0, 5.25));
    EXPECT_EQ(height(13.5, -0.5), f(12.0, 0.0));
    EXPECT_EQ(height(40.0, 40.0), f(12.0, 12.0));
}

} // namespace
} // namespace pyramid
