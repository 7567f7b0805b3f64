// DEM tiles as PNG (`pyramid tile -o x.png`): a 16-bit grey PNG that reads back to the tile's
// elevations within the quantization of its range, and with --hillshade the tile drawn as the
// preview draws a level, its borders included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <string>

#include "libpyramid/preview/shading.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/preview_pngs.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::demOf;
using test::Png;
using test::readPng;
using test::TempDir;

TEST(TilePng, ADemTileIsA16BitGreyPngOfItsRange) {
    TempDir dir;
    const std::string dem = demOf(dir, "hill", 65, [](double x, double y) { return 50.0 + x * x * 0.1 - y; });
    const test::RunResult run =
        test::run(test::programPath("pyramid") + " tile " + dem + " 1 0 0 -o " + dir.file("t.png"));
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const Png png = readPng(dir.file("t.png"));
    ASSERT_EQ(png.depth, 16);
    ASSERT_EQ(png.channels, 1);
    ASSERT_EQ(png.width, 37); // 32 intervals + 5
    const double lo = std::stod(png.text.at("Minimum")), hi = std::stod(png.text.at("Maximum"));
    const FileLevelProducer producer = makeFileLevelProducer(dem, 1);
    const auto tile = producer.fileTile(1, 0, 0);
    ASSERT_EQ(tile->zf.size(), png.samples.size());
    EXPECT_EQ(lo, *std::min_element(tile->zf.begin(), tile->zf.end()));
    EXPECT_EQ(hi, *std::max_element(tile->zf.begin(), tile->zf.end()));
    for (int j = 0; j < 37; ++j) {
        for (int i = 0; i < 37; ++i) {
            const double grey = png.samples[static_cast<size_t>(36 - j) * 37 + i]; // north up
            EXPECT_NEAR(lo + grey / 65535.0 * (hi - lo), tile->zf[static_cast<size_t>(j) * 37 + i],
                        (hi - lo) / 65535.0);
        }
    }
}

// `pyramid tile --hillshade`: a DEM tile as the preview draws a level, its borders included: a
// tilted plane's light is the plane's wherever the tile's samples are the plane's (the borders
// beyond the map's edges hold what the encoder filled them with).
TEST(TilePng, AHillshadedTileOfAPlaneIsUniform) {
    TempDir dir;
    const std::string plane = demOf(dir, "plane", 65, [](double x, double y) { return 100.0 + 0.7 * x + 0.4 * y; });
    const std::string tile = test::programPath("pyramid") + " tile " + plane + " 1 1 0 ";
    const test::RunResult run = test::run(tile + "--hillshade -o " + dir.file("t.png"));
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const Png png = readPng(dir.file("t.png"));
    ASSERT_EQ(png.width, 37);
    ASSERT_EQ(png.height, 37);
    ASSERT_EQ(png.channels, 3);
    EXPECT_EQ(png.text.at("Style"), "hillshade");
    // The colours vary with height; the light does not: each pixel is its height's colour shaded
    // by the plane's light (the plane's samples are exact to the file's quantization).
    const FileLevelProducer producer = makeFileLevelProducer(plane, 1);
    const auto heights = producer.fileTile(1, 1, 0);
    const double lo = std::stod(png.text.at("Minimum height")), hi = std::stod(png.text.at("Maximum height"));
    const double light = hillshade(0.7, 0.4);
    int far = 0;
    for (int j = 3; j <= 33; ++j) {
        for (int i = 3; i <= 33; ++i) {
            const Rgb8 want = shaded(hypsometricColour((heights->zf[static_cast<size_t>(j) * 37 + i] - lo) / (hi - lo)), light);
            const size_t k = (static_cast<size_t>(36 - j) * 37 + i) * 3;
            for (int c = 0; c < 3; ++c) {
                far += std::abs(png.samples[k + c] / 257 - want[static_cast<size_t>(c)]) > 2;
            }
        }
    }
    EXPECT_EQ(far, 0);
    EXPECT_EQ(test::run(tile + "--hillshade --residual -o " + dir.file("r.png")).exitCode, 1);
    const test::RunResult tif = test::run(tile + "--hillshade -o " + dir.file("t.tif"));
    EXPECT_EQ(tif.exitCode, 1);
    EXPECT_NE(tif.err.find("--hillshade draws a PNG"), std::string::npos) << tif.err;
    EXPECT_FALSE(fs::exists(dir.file("r.png")));
}

} // namespace
} // namespace pyramid
