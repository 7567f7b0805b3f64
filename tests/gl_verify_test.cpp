// verifyOnGl, the library side of `pyramid verify FILE --gl`: the original tools' DEM.dat and
// RGB.dat, a small residual pyramid with extreme residuals and an inexact scale written with
// the formats writer, a DXT ortho file, and the files the preprocessors make (planar DEM with
// several elevation tile sizes and delta > 0, all three ortho outputs, a cube face); every tile
// compared, CPU against GPU.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/gl/gl_verify.hpp"
#include "tests/support/gl_test_context.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

const GlVerifyPart* findPart(const GlVerifyReport& r, const std::string& what) {
    for (const GlVerifyPart& p : r.parts) {
        if (p.what == what) {
            return &p;
        }
    }
    return nullptr;
}

void expectExact(const GlVerifyReport& r, const std::string& what, int64_t tiles) {
    const GlVerifyPart* p = findPart(r, what);
    ASSERT_NE(p, nullptr) << what << " missing from the report of " << r.file;
    EXPECT_EQ(p->tiles, tiles) << what;
    EXPECT_EQ(p->differingTiles, 0) << what;
    EXPECT_EQ(p->maxDifference, 0.0) << what;
}

TEST(GlVerify, UlpDistance) {
    EXPECT_EQ(ulpDistance(1.0f, 1.0f), 0u);
    EXPECT_EQ(ulpDistance(1.0f, std::nextafter(1.0f, 2.0f)), 1u);
    EXPECT_EQ(ulpDistance(0.0f, -0.0f), 1u);
    EXPECT_EQ(ulpDistance(-std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::denorm_min()), 3u);
    EXPECT_EQ(ulpDistance(-1.0f, std::nextafter(-1.0f, -2.0f)), 1u);
}

TEST(GlVerify, AnyDifferenceBeyondTheToleranceFailsTheReport) {
    GlVerifyReport r;
    EXPECT_FALSE(r.ok()); // nothing compared is no proof
    r.parts.push_back({"elevation n=24 delta=0", "ulp", 10, 0, 0.0, 0.0});
    r.parts.push_back({"DXT decoded colours", "abs", 10, 3, 3.0, kDxtDecodeTolerance});
    EXPECT_TRUE(r.ok());
    r.parts[0].differingTiles = 1;
    r.parts[0].maxDifference = 1.0; // one ulp in one tile
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(toJson(r)["ok"], false);
    r.parts[0] = {"elevation n=24 delta=0", "ulp", 10, 0, 0.0, 0.0};
    r.parts[1].maxDifference = kDxtDecodeTolerance + 1.0;
    EXPECT_FALSE(r.ok());
}

TEST(GlVerify, OriginalDemEveryTileSize) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    const GlVerifyReport r = verifyOnGl(test::dataPath("proland/DEM.dat"));
    EXPECT_TRUE(r.ok());
    EXPECT_FALSE(r.renderer.empty());
    ASSERT_EQ(r.parts.size(), 4u);
    expectExact(r, "elevation n=192 delta=3", 1 + 4 + 16);
    expectExact(r, "elevation n=96 delta=2", 1 + 4 + 16 + 64);
    expectExact(r, "elevation n=48 delta=1", 341);
    expectExact(r, "elevation n=24 delta=0", 1365);
    EXPECT_EQ(toJson(r)["ok"], true);
}

TEST(GlVerify, CommandLineReportsAndExitsZero) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    const test::RunResult r =
        test::run(test::programPath("pyramid") + " verify " + test::dataPath("proland/RGB.dat") + " --gl --json");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["ok"], true);
    ASSERT_EQ(j["parts"].size(), 2u);
    EXPECT_EQ(j["parts"][1]["what"], "colour residuals");
    EXPECT_EQ(j["parts"][1]["tiles"], 5);
    const test::RunResult both = test::run(test::programPath("pyramid") + " verify " +
                                           test::dataPath("proland/RGB.dat") + " --gl --source x.tif");
    EXPECT_EQ(both.exitCode, 2) << both.err; // --gl compares CPU and GPU, not a source
}

TEST(GlVerify, MaxLevelLimitsTheWalk) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    GlVerifyOptions o;
    o.maxLevel = 1;
    const GlVerifyReport r = verifyOnGl(test::dataPath("proland/DEM.dat"), o);
    expectExact(r, "elevation n=24 delta=0", 5);
}

TEST(GlVerify, OriginalOrthoAsTilesAndAsColourResiduals) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    const GlVerifyReport r = verifyOnGl(test::dataPath("proland/RGB.dat"));
    EXPECT_TRUE(r.ok());
    expectExact(r, "ortho tiles", 5);
    expectExact(r, "colour residuals", 5);
}

TEST(GlVerify, SmallPyramidWithExtremeResiduals) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    test::TempDir dir;
    ResidualHeader h;
    h.minLevel = 2;
    h.maxLevel = 3;
    h.tileSize = 16;
    h.scale = 0.37f; // inexact products
    const std::string path = dir.file("small.dat");
    {
        ResidualFileWriter w(path, h);
        std::mt19937 rng(3);
        std::uniform_int_distribution<int> r(-32768, 32767);
        for (int level = 0; level <= h.maxLevel; ++level) {
            for (int64_t ty = 0; ty < h.tilesPerSide(level); ++ty) {
                for (int64_t tx = 0; tx < h.tilesPerSide(level); ++tx) {
                    std::vector<int16_t> samples(static_cast<size_t>(h.tileSamples(level) * h.tileSamples(level)));
                    for (int16_t& s : samples) {
                        s = static_cast<int16_t>(r(rng) % (level == 0 ? 32768 : 64));
                    }
                    samples[0] = 32767;
                    samples[1] = -32768;
                    w.writeTile(level, static_cast<int>(tx), static_cast<int>(ty), samples);
                }
            }
        }
        w.commit();
    }
    const GlVerifyReport r = verifyOnGl(path);
    EXPECT_TRUE(r.ok());
    expectExact(r, "elevation n=16 delta=2", 1 + 4);
    expectExact(r, "elevation n=8 delta=1", 1 + 4 + 16);
    expectExact(r, "elevation n=4 delta=0", 1 + 4 + 16 + 64);
}

TEST(GlVerify, DxtOrthoKeepsBlocksAndDecodesWithinTolerance) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = 28;
    h.channels = 4;
    h.flags = OrthoHeader::kFlagDxt;
    const std::string path = dir.file("dxt.dat");
    {
        OrthoFileWriter w(path, h);
        for (int level = 0; level <= 1; ++level) {
            for (int t = 0; t < (1 << (2 * level)); ++t) {
                std::vector<uint8_t> pixels(32 * 32 * 4);
                for (size_t k = 0; k < pixels.size(); ++k) {
                    pixels[k] = static_cast<uint8_t>((k * 7 + static_cast<size_t>(t) * 13 + (k / 128) * 5) % 256);
                }
                w.writeTile(level, t % (1 << level), t >> level, pixels);
            }
        }
        w.commit();
    }
    const GlVerifyReport r = verifyOnGl(path);
    EXPECT_TRUE(r.ok());
    expectExact(r, "dxt blocks", 5);
    const GlVerifyPart* decoded = findPart(r, "dxt decoding");
    ASSERT_NE(decoded, nullptr);
    EXPECT_EQ(decoded->tiles, 5);
    EXPECT_LE(decoded->maxDifference, kDxtDecodeTolerance);
    EXPECT_EQ(findPart(r, "colour residuals"), nullptr); // DXT files hold no residuals
}

TEST(GlVerify, PreprocessorOutputsEveryTileSize) {
    PYRAMID_GL_CONTEXT_OR_SKIP();
    test::TempDir dir;
    // 129 x 129 heights, 16-tiles with a 4-interval root: minLevel 2, maxLevel 5, so elevation
    // tiles of 16, 8 and 4 intervals with delta 2, 1 and 0.
    test::writeFloatRaster(dir.file("dem.tif"), 129, 129, test::syntheticHeights(129, 129));
    const test::RunResult dem = test::run(test::programPath("preprocessDem") + " " + dir.file("dem.tif") + " -o " +
                                          dir.file("DEM.dat") + " --tile-size 16 --root-tile-size 4 --scale 0.1 -q");
    ASSERT_EQ(dem.exitCode, 0) << dem.err;
    const GlVerifyReport d = verifyOnGl(dir.file("DEM.dat"));
    EXPECT_TRUE(d.ok());
    ASSERT_EQ(d.parts.size(), 3u);
    const int64_t deep = 1 + 4 + 16 + 64; // levels 2..5 of the file as 16-tiles
    expectExact(d, "elevation n=16 delta=2", deep);
    expectExact(d, "elevation n=8 delta=1", deep + 256);
    expectExact(d, "elevation n=4 delta=0", deep + 256 + 1024);

    // All three ortho outputs of a 64 x 64 image in 16-tiles (levels 0..2).
    std::vector<uint16_t> pixels(64 * 64 * 3);
    for (size_t k = 0; k < pixels.size(); ++k) {
        pixels[k] = static_cast<uint16_t>((k * 37 + k / 192 * 11) % 256);
    }
    test::writeImage(dir.file("rgb.png"), 64, 64, 3, pixels, false);
    const test::RunResult ortho = test::run(test::programPath("preprocessOrtho") + " " + dir.file("rgb.png") +
                                            " -o " + dir.file("ortho") + " --tile-size 16 -q");
    ASSERT_EQ(ortho.exitCode, 0) << ortho.err;
    for (const char* file : {"ortho/RGB.dat", "ortho/dxt/RGB.dat", "ortho/residuals/RGB.dat"}) {
        const GlVerifyReport r = verifyOnGl(dir.file(file));
        EXPECT_TRUE(r.ok()) << file;
        EXPECT_FALSE(r.parts.empty()) << file;
        for (const GlVerifyPart& p : r.parts) {
            EXPECT_EQ(p.tiles, 1 + 4 + 16) << file << " " << p.what;
        }
    }

    // A cube face of the spherical preprocessor.
    const test::RunResult sphere =
        test::run(test::programPath("preprocessSphericalDem") + " " + test::samplePath("srtm.png") + " -o " +
                  dir.file("planet") + " --tile-size 16 --root-tile-size 8 --max-level 3 --height-scale 10000/255 "
                  "--faces 2 -q");
    ASSERT_EQ(sphere.exitCode, 0) << sphere.err;
    const GlVerifyReport f = verifyOnGl(dir.file("planet/DEM2.dat"));
    EXPECT_TRUE(f.ok());
    expectExact(f, "elevation n=16 delta=1", 1 + 4 + 16);
    expectExact(f, "elevation n=8 delta=0", 1 + 4 + 16 + 64);
}

} // namespace
} // namespace pyramid
