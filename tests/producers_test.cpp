// Producers over several files (a main pyramid and nested regions) and the colour-residual
// producer, on small pyramids written here with hand-picked values.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <tuple>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/capi/pyramid.h"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/filters/colour_upsample.hpp"
#include "tests/support/c_api_sources.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

// Residual tile whose every sample is `base + i + 3 j`.
std::vector<int16_t> ramp(int size, int base) {
    std::vector<int16_t> r(static_cast<size_t>(size) * size);
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            r[static_cast<size_t>(i + j * size)] = static_cast<int16_t>(base + i + 3 * j);
        }
    }
    return r;
}

TEST(ResidualRegions, RegionTilesReplaceAndExtendTheMainPyramid) {
    test::TempDir dir;
    ResidualHeader main;
    main.minLevel = 1;
    main.maxLevel = 2;
    main.tileSize = 4;
    main.scale = 0.5f;
    {
        ResidualFileWriter w(dir.file("main.dat"), main);
        w.writeTile(0, 0, 0, ramp(main.tileSamples(0), 100));
        w.writeTile(1, 0, 0, ramp(9, 1));
        for (int t = 0; t < 4; ++t) {
            w.writeTile(2, t % 2, t / 2, ramp(9, 10 * t));
        }
        w.commit();
    }
    ResidualHeader region;
    region.minLevel = 0;
    region.maxLevel = 1;
    region.tileSize = 4;
    region.rootLevel = 2;
    region.rootTx = 1;
    region.rootTy = 1;
    region.scale = 0.25f;
    {
        ResidualFileWriter w(dir.file("region.dat"), region);
        w.writeTile(0, 0, 0, ramp(9, -7));
        for (int t = 0; t < 4; ++t) {
            w.writeTile(1, t % 2, t / 2, ramp(9, 50 + t));
        }
        w.commit();
    }
    ResidualProducerOptions ro;
    ro.delta = 1; // elevation tiles of 4: minLevel - log2(4/4)
    auto residuals = std::make_shared<ResidualProducer>(dir.file("main.dat"),
                                                        std::vector<std::string>{dir.file("region.dat")}, ro);
    EXPECT_EQ(residuals->maxLevel(), 2); // absolute level 3, producer level 3 - delta
    EXPECT_TRUE(residuals->hasTile(1, 1, 1));
    EXPECT_TRUE(residuals->hasTile(2, 3, 2));  // inside the region
    EXPECT_FALSE(residuals->hasTile(2, 0, 0)); // beyond the main file, outside the region
    // (2,1,1) comes from the region's root, at the region's scale.
    const std::vector<float> r = residuals->tile(1, 1, 1);
    EXPECT_EQ(r[0], -7.0f * 0.25f);
    EXPECT_EQ(residuals->tile(1, 0, 1)[0], 20.0f * 0.5f); // main file, tile index 2
    ElevationProducerOptions eo;
    eo.tileSize = 4;
    ElevationProducer producer(residuals, eo);
    const auto parent = producer.tile(0, 0, 0);
    const auto child = producer.tile(1, 1, 1);
    std::vector<float> expected = residuals->tile(1, 1, 1);
    upsampleAndAdd(parent->zf.data(), 9, 4, quadrantOffset(1, 4), quadrantOffset(1, 4), expected.data(), 9);
    EXPECT_EQ(child->zf, expected);
    // Outside the region, past the main file: no residual, a smooth continuation.
    const auto smooth = producer.tile(2, 0, 0);
    std::vector<float> zeros(81, 0.0f);
    upsampleAndAdd(producer.tile(1, 0, 0)->zf.data(), 9, 4, 1, 1, zeros.data(), 9);
    EXPECT_EQ(smooth->zf, zeros);
    // Inside it: the region's level 1.
    const auto deep = producer.tile(2, 3, 2);
    std::vector<float> deepExpected = residuals->tile(2, 3, 2);
    EXPECT_EQ(deepExpected[0], 51.0f * 0.25f); // region tile (1,1,0)
    upsampleAndAdd(child->zf.data(), 9, 4, quadrantOffset(3, 4), quadrantOffset(2, 4), deepExpected.data(), 9);
    EXPECT_EQ(deep->zf, deepExpected);
}

TEST(ResidualRegions, NestedRegionsTheDeepestWins) {
    test::TempDir dir;
    // main: levels 0..2 (minLevel 1); region A rooted at (2, 1, 1) adds levels 2..3; region B,
    // inside A, rooted at (3, 2, 2), adds levels 3..4. Every file has its own scale.
    test::writeResidualSet(dir);
    ResidualProducerOptions ro;
    ro.delta = 1; // producer level = file level - 1
    for (const auto& regions : {std::vector<std::string>{dir.file("a.dat"), dir.file("b.dat")},
                                std::vector<std::string>{dir.file("b.dat"), dir.file("a.dat")}}) {
        const ResidualProducer residuals(dir.file("main.dat"), regions, ro);
        EXPECT_EQ(residuals.tile(1, 0, 0)[0], 0.5f * (100 + 20 + 0));   // main, level 2, tile 0
        EXPECT_EQ(residuals.tile(1, 1, 1)[0], 0.25f * (200 + 0));       // A's root replaces main's (2,1,1)
        EXPECT_EQ(residuals.tile(2, 3, 3)[0], 0.25f * (200 + 10 + 3));  // A's level 1, tile (1, 1)
        EXPECT_EQ(residuals.tile(2, 2, 2)[0], 0.125f * (300 + 0));      // B's root wins over A's (0, 0)
        EXPECT_EQ(residuals.tile(3, 5, 4)[0], 0.125f * (300 + 10 + 1)); // B's level 1, tile (1, 0)
        EXPECT_TRUE(residuals.hasTile(3, 5, 4));
        EXPECT_FALSE(residuals.hasTile(3, 6, 6)); // in A, below A's last level, outside B
        EXPECT_FALSE(residuals.hasTile(3, 0, 0)); // beyond every file
    }
    // The C API serves the same elevations as the C++ producer over the same three files.
    ElevationProducerOptions eo;
    eo.tileSize = 2; // n = tileSize / 2: k = 1 = minLevel, so delta 0
    ResidualProducerOptions r0;
    r0.delta = 0;
    ElevationProducer cpp(std::make_shared<ResidualProducer>(
                              dir.file("main.dat"), std::vector<std::string>{dir.file("a.dat"), dir.file("b.dat")}, r0),
                          eo);
    const std::string a = dir.file("a.dat"), b = dir.file("b.dat");
    const char* regions[] = {a.c_str(), b.c_str()};
    pyramid_elevation* c = nullptr;
    ASSERT_EQ(pyramid_elevation_open_regions(dir.file("main.dat").c_str(), regions, 2, 2, 0, 16, &c), PYRAMID_OK)
        << pyramid_last_error();
    ASSERT_EQ(pyramid_elevation_side(c), 7);
    std::vector<float> zf(49);
    for (const auto& [level, tx, ty] : {std::tuple{1, 0, 0}, std::tuple{3, 2, 2}, std::tuple{4, 5, 4}, std::tuple{4, 0, 0}}) {
        ASSERT_EQ(pyramid_elevation_tile(c, level, tx, ty, zf.data(), nullptr, nullptr, zf.size()), PYRAMID_OK)
            << pyramid_last_error();
        EXPECT_EQ(zf, cpp.tile(level, tx, ty)->zf) << level << " " << tx << " " << ty;
    }
    pyramid_elevation_close(c);
    const char* missing[] = {nullptr};
    EXPECT_EQ(pyramid_elevation_open_regions(dir.file("main.dat").c_str(), missing, 1, 2, 0, 16, &c),
              PYRAMID_ERROR_ARGUMENT);
}

TEST(ResidualRegions, MismatchedRegionsAreRefused) {
    test::TempDir dir;
    ResidualHeader h;
    h.minLevel = 0;
    h.maxLevel = 0;
    h.tileSize = 8;
    {
        ResidualFileWriter w(dir.file("main.dat"), h);
        w.writeTile(0, 0, 0, ramp(13, 0));
        w.commit();
    }
    h.rootLevel = 1;
    h.tileSize = 4;
    {
        ResidualFileWriter w(dir.file("region.dat"), h);
        w.writeTile(0, 0, 0, ramp(9, 0));
        w.commit();
    }
    EXPECT_THROW(ResidualProducer(dir.file("main.dat"), {dir.file("region.dat")}), Error);
}

// Leaves tile `index` of the pyramid file `path` out: its byte range made empty (end moved onto
// begin), as a file may store it (doc/format.md). `offsetBytes`: 4 (residual) or 8 (ortho).
void leaveOut(const std::string& path, int64_t index, int offsetBytes) {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    const auto entry = static_cast<std::streamoff>(ResidualHeader::kBytes) + index * 2 * offsetBytes;
    std::vector<char> begin(static_cast<size_t>(offsetBytes));
    f.seekg(entry);
    f.read(begin.data(), offsetBytes);
    f.seekp(entry + offsetBytes);
    f.write(begin.data(), offsetBytes);
    ASSERT_TRUE(f.good()) << path;
}

// A tile left out (an empty byte range) has zero residuals, for the tile and every tile below it:
// the elevations continue smoothly, as beyond the file.
TEST(ResidualRegions, ATileLeftOutHasZeroResiduals) {
    test::TempDir dir;
    ResidualHeader h;
    h.minLevel = 1;
    h.maxLevel = 2;
    h.tileSize = 4;
    {
        ResidualFileWriter w(dir.file("main.dat"), h);
        w.writeTile(0, 0, 0, ramp(h.tileSamples(0), 100));
        w.writeTile(1, 0, 0, ramp(9, 1));
        for (int t = 0; t < 4; ++t) {
            w.writeTile(2, t % 2, t / 2, ramp(9, 10 + 10 * t));
        }
        w.commit();
    }
    leaveOut(dir.file("main.dat"), h.tileIndex(2, 1, 0), 4);
    ResidualProducerOptions ro;
    ro.delta = 1;
    auto residuals = std::make_shared<ResidualProducer>(dir.file("main.dat"), std::vector<std::string>{}, ro);
    EXPECT_FALSE(residuals->hasTile(1, 1, 0));
    EXPECT_TRUE(residuals->hasTile(1, 0, 0));
    EXPECT_EQ(residuals->tile(1, 1, 0), std::vector<float>(81, 0.0f));
    ElevationProducerOptions eo;
    eo.tileSize = 4;
    ElevationProducer producer(residuals, eo);
    std::vector<float> expected(81, 0.0f);
    upsampleAndAdd(producer.tile(0, 0, 0)->zf.data(), 9, 4, quadrantOffset(1, 4), quadrantOffset(0, 4), expected.data(),
                   9);
    const auto leftOut = producer.tile(1, 1, 0);
    EXPECT_EQ(leftOut->zf, expected);
    std::vector<float> below(81, 0.0f);
    upsampleAndAdd(leftOut->zf.data(), 9, 4, quadrantOffset(3, 4), quadrantOffset(1, 4), below.data(), 9);
    EXPECT_EQ(producer.tile(2, 3, 1)->zf, below);

    // The root with delta 1 folds file levels 0 and 1: one of them left out is zero, not missing.
    leaveOut(dir.file("main.dat"), h.tileIndex(0, 0, 0), 4);
    const ResidualProducer folded(dir.file("main.dat"), {}, ro);
    EXPECT_TRUE(folded.hasTile(0, 0, 0));
    std::vector<float> root(81, 0.0f);
    const std::vector<int16_t> level1 = ramp(9, 1);
    std::vector<float> zeros(81, 0.0f);
    for (size_t k = 0; k < root.size(); ++k) {
        root[k] = static_cast<float>(level1[k]) * h.scale;
    }
    upsampleAndAdd(zeros.data(), 9, 4, 1, 1, root.data(), 9);
    EXPECT_EQ(folded.tile(0, 0, 0), root);
    leaveOut(dir.file("main.dat"), h.tileIndex(1, 0, 0), 4);
    EXPECT_FALSE(ResidualProducer(dir.file("main.dat"), {}, ro).hasTile(0, 0, 0));
}

std::vector<uint8_t> solid(int side, int channels, uint8_t base) {
    std::vector<uint8_t> p(static_cast<size_t>(side) * side * channels);
    for (size_t k = 0; k < p.size(); ++k) {
        p[k] = static_cast<uint8_t>(base + k % 7);
    }
    return p;
}

TEST(OrthoProducer, ServesMainAndRegionTiles) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = 8;
    h.channels = 3;
    {
        OrthoFileWriter w(dir.file("main.dat"), h);
        for (int i = 0; i < 5; ++i) {
            const int l = i == 0 ? 0 : 1;
            w.writeTile(l, l ? (i - 1) % 2 : 0, l ? (i - 1) / 2 : 0, solid(12, 3, static_cast<uint8_t>(10 * i)));
        }
        w.commit();
    }
    OrthoHeader r = h;
    r.rootLevel = 1;
    r.rootTx = 1;
    r.rootTy = 0;
    {
        OrthoFileWriter w(dir.file("region.dat"), r);
        for (int i = 0; i < 5; ++i) {
            const int l = i == 0 ? 0 : 1;
            w.writeTile(l, l ? (i - 1) % 2 : 0, l ? (i - 1) / 2 : 0, solid(12, 3, static_cast<uint8_t>(100 + i)));
        }
        w.commit();
    }
    OrthoProducer p(dir.file("main.dat"), {dir.file("region.dat")});
    EXPECT_EQ(p.maxLevel(), 2);
    EXPECT_EQ(p.tile(1, 0, 0), solid(12, 3, 10));  // main
    EXPECT_EQ(p.tile(1, 1, 0), solid(12, 3, 100)); // the region's root replaces main's (1,1,0)
    EXPECT_EQ(p.tile(2, 3, 1), solid(12, 3, 104)); // region (1,1,1)
    EXPECT_FALSE(p.hasTile(2, 0, 0));
    EXPECT_THROW(p.tile(2, 0, 0), Error);
    EXPECT_EQ(p.rawTile(0, 0, 0), OrthoFileReader::open(dir.file("main.dat"))->readTileBytes(0, 0, 0));
}

TEST(OrthoProducer, ReadsTheOriginalFile) {
    OrthoProducer p(test::dataPath("proland/RGB.dat"));
    const auto reader = OrthoFileReader::open(test::dataPath("proland/RGB.dat"));
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(p.tile(1, i % 2, i / 2), reader->readTile(1, i % 2, i / 2));
    }
}

TEST(ColourProducer, RebuildsChildrenFromResiduals) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = 4; // 8 x 8 pixels with borders
    h.channels = 1;
    std::vector<uint8_t> root(64);
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) {
            root[static_cast<size_t>(x + 8 * y)] = static_cast<uint8_t>(16 * x + y);
        }
    }
    std::vector<uint8_t> flat(64, 128);
    std::vector<uint8_t> bumped = flat;
    bumped[3 + 8 * 2] = 138; // +20 at child pixel (3, 2)
    {
        OrthoFileWriter w(dir.file("residuals.dat"), h);
        w.writeTile(0, 0, 0, root);
        w.writeTile(1, 0, 0, flat);
        w.writeTile(1, 1, 0, bumped);
        w.writeTile(1, 0, 1, flat);
        w.writeTile(1, 1, 1, flat);
        w.commit();
    }
    ColourProducer p(std::make_shared<OrthoProducer>(dir.file("residuals.dat")));
    EXPECT_EQ(*p.tile(0, 0, 0), root);
    const auto child = p.tile(1, 1, 0);
    // Child (3, 2) of quadrant (1, 0): bx = (3+1)/2 + 2 = 4, by = (2+1)/2 + 0 = 1; odd x weighs
    // (3, 1), even y weighs (1, 3): (1*(3*p(4,1) + 1*p(5,1)) + 3*(3*p(4,2) + 1*p(5,2))) >> 4.
    auto p0 = [&](int x, int y) { return static_cast<unsigned>(root[static_cast<size_t>(x + 8 * y)]); };
    const unsigned prediction = (1 * (3 * p0(4, 1) + p0(5, 1)) + 3 * (3 * p0(4, 2) + p0(5, 2))) >> 4;
    EXPECT_EQ((*child)[3 + 8 * 2], prediction + 20);
    EXPECT_EQ((*child)[2 + 8 * 2], predictColour(root.data(), 8, 1, 0, 2, 0, 2, 2));
    // Beyond the file: "no residual" everywhere, the prediction alone.
    const auto beyond = p.tile(2, 2, 0);
    std::vector<uint8_t> expected(64);
    upsampleColour(child->data(), 4, 1, 2, 0, nullptr, expected.data());
    EXPECT_EQ(*beyond, expected);

    // A tile left out (an empty byte range): no residual either, at the tile and below.
    leaveOut(dir.file("residuals.dat"), h.tileIndex(1, 0, 1), 8);
    const auto tiles = std::make_shared<OrthoProducer>(dir.file("residuals.dat"));
    EXPECT_FALSE(tiles->hasTile(1, 0, 1));
    EXPECT_THROW(tiles->tile(1, 0, 1), MissingTileError);
    ColourProducer q(tiles);
    const auto leftOut = q.tile(1, 0, 1);
    upsampleColour(root.data(), 4, 1, 0, 1, nullptr, expected.data());
    EXPECT_EQ(*leftOut, expected);
    upsampleColour(leftOut->data(), 4, 1, 1, 3, nullptr, expected.data());
    EXPECT_EQ(*q.tile(2, 1, 3), expected);
    EXPECT_EQ(*q.tile(1, 1, 0), *child);
}

// The row predictor sums the same integers as the per-sample formula, in another order: equal
// for every channel count, quadrant, row and column (parents with extreme values included).
TEST(OrthoUpsample, RowPredictionIsThePerSampleFormula) {
    for (const int tileSize : {2, 8, 30, 31}) { // 31: a side of odd width
        const int side = tileSize + 4;
        for (int channels = 1; channels <= 4; ++channels) {
            const size_t rowBytes = static_cast<size_t>(side) * channels;
            std::vector<uint8_t> parent(rowBytes * side);
            for (size_t k = 0; k < parent.size(); ++k) {
                parent[k] = k % 11 == 0 ? 255 : k % 13 == 0 ? 0 : static_cast<uint8_t>((k * 2654435761u) >> 24);
            }
            std::vector<uint8_t> row(rowBytes);
            for (int q = 0; q < 4; ++q) {
                const int rx = (q & 1) * (tileSize / 2), ry = (q >> 1) * (tileSize / 2);
                for (int y = 0; y < side; ++y) {
                    predictColourRow(parent.data(), rowBytes, channels, rx, ry, y, side, row.data());
                    for (int x = 0; x < side; ++x) {
                        for (int c = 0; c < channels; ++c) {
                            ASSERT_EQ(row[static_cast<size_t>(x * channels + c)],
                                      predictColour(parent.data(), rowBytes, channels, c, rx, ry, x, y))
                                << tileSize << " " << channels << " channels, quadrant " << q << ", pixel " << x
                                << "," << y << " channel " << c;
                        }
                    }
                }
            }
        }
    }
}

// The encoder's one pass over a row of Deflate residuals gives the stored values and rebuilt
// samples of the two formulas, for every value and prediction; its error count is the number
// of rebuilt samples off their values (each by one, none clamped) and its spread the sum of
// |stored - 128|.
TEST(OrthoUpsample, ResidualsAndRebuiltSamplesInOnePassAreTheFormulas) {
    std::vector<uint8_t> values, predictions;
    for (int v = 0; v < 256; ++v) {
        for (int p = 0; p < 256; ++p) {
            values.push_back(static_cast<uint8_t>(v));
            predictions.push_back(static_cast<uint8_t>(p));
        }
    }
    for (const size_t count : {values.size(), size_t{37}}) { // a whole vector's worth, and a remainder
        std::vector<uint8_t> rebuilt(predictions.begin(), predictions.begin() + static_cast<std::ptrdiff_t>(count));
        std::vector<uint8_t> stored(count);
        const RebuiltRow row = encodeColourResidualsRebuilt(values.data(), rebuilt.data(), count, stored.data());
        int64_t errors = 0, spread = 0;
        for (size_t k = 0; k < count; ++k) {
            bool clamped = true;
            ASSERT_EQ(stored[k], encodeColourResidual(values[k], predictions[k], &clamped)) << k;
            EXPECT_FALSE(clamped);
            ASSERT_EQ(rebuilt[k], applyColourResidual(predictions[k], stored[k])) << k;
            const int error = std::abs(rebuilt[k] - values[k]);
            ASSERT_LE(error, 1);
            errors += error;
            spread += std::abs(stored[k] - 128);
        }
        EXPECT_EQ(row.errors, errors);
        EXPECT_EQ(row.spread, spread);
        EXPECT_GT(errors, 0);
    }
}

} // namespace
} // namespace pyramid
