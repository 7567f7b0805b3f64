// Previews (`pyramid preview`, libpyramid/preview/) of planar pyramids: shading's light and colour
// ramps; a tilted plane's hillshade is uniform and a cone's is not; the PNG has the level's size
// and its range in its text; an ortho level's preview is its tiles' pixels; a legend is the
// colour bar of the range.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/preview/preview.hpp"
#include "libpyramid/preview/shading.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/preview_pngs.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::demOf;
using test::Png;
using test::readPng;
using test::TempDir;

// The grey levels of a shade preview, without its outermost ring of pixels.
std::vector<int> innerGreys(const Png& png) {
    std::vector<int> grey;
    for (int y = 1; y + 1 < png.height; ++y) {
        for (int x = 1; x + 1 < png.width; ++x) {
            grey.push_back(png.samples[(static_cast<size_t>(y) * png.width + x) * png.channels] >> 8);
        }
    }
    return grey;
}

TEST(Shading, FlatGroundFacesTheSunAtItsAltitudeAndSlopesTurnFromIt) {
    EXPECT_NEAR(hillshade(0, 0, 315, 45), std::sin(45.0 * M_PI / 180.0), 1e-12);
    EXPECT_NEAR(hillshade(0, 0, 0, 90), 1.0, 1e-12);
    // A slope rising to the east faces west: lit by a western sun, in shadow from a low eastern one.
    EXPECT_GT(hillshade(1.0, 0.0, 270, 30), hillshade(0, 0, 270, 30));
    EXPECT_EQ(hillshade(3.0, 0.0, 90, 10), 0.0);
    EXPECT_EQ(hypsometricColour(0.0), (Rgb8{46, 110, 58}));
    EXPECT_EQ(hypsometricColour(1.0), (Rgb8{250, 250, 250}));
    EXPECT_EQ(divergingColour(0.0), (Rgb8{247, 247, 247}));
    EXPECT_GT(divergingColour(1.0)[0], divergingColour(1.0)[2]);
    EXPECT_GT(divergingColour(-1.0)[2], divergingColour(-1.0)[0]);
}

TEST(Preview, ATiltedPlanesHillshadeIsUniformAndAConesIsNot) {
    TempDir dir;
    const std::string plane = demOf(dir, "plane", 129, [](double x, double y) { return 100.0 + 0.7 * x + 0.4 * y; });
    PreviewOptions o;
    o.style = PreviewStyle::Shade;
    o.spacing = 1.0;
    const PreviewReport r = writePreview(plane, dir.file("plane.png"), o);
    EXPECT_EQ(r.level, 2);
    EXPECT_EQ(r.width, 129);
    const std::vector<int> flat = innerGreys(readPng(dir.file("plane.png")));
    ASSERT_FALSE(flat.empty());
    const auto [lo, hi] = std::minmax_element(flat.begin(), flat.end());
    EXPECT_LE(*hi - *lo, 2) << "a plane has one slope (up to its heights' quantization)";
    // The plane's expected light: its normal against the default sun.
    EXPECT_NEAR(flat[flat.size() / 2], 255.0 * hillshade(0.7, 0.4), 1.5);

    const std::string cone = demOf(dir, "cone", 129, [](double x, double y) {
        return 500.0 - 3.0 * std::hypot(x - 64.0, y - 64.0);
    });
    writePreview(cone, dir.file("cone.png"), o);
    const std::vector<int> sides = innerGreys(readPng(dir.file("cone.png")));
    const auto [dark, bright] = std::minmax_element(sides.begin(), sides.end());
    EXPECT_GT(*bright - *dark, 150) << "a cone's sides face every way";
}

TEST(Preview, ThePngHasTheLevelsSizeAndItsRangeInItsText) {
    TempDir dir;
    const std::string dem = demOf(dir, "hill", 257, [](double x, double y) {
        return 1000.0 * std::exp(-((x - 100) * (x - 100) + (y - 150) * (y - 150)) / 4000.0);
    });
    PreviewOptions o;
    o.size = 200; // levels of 33, 65, 129 and 257 samples: level 2
    const PreviewReport r = writePreview(dem, dir.file("hill.png"), o);
    EXPECT_EQ(r.level, 2);
    const Png png = readPng(dir.file("hill.png"));
    EXPECT_EQ(png.width, 129);
    EXPECT_EQ(png.height, 129);
    EXPECT_EQ(png.channels, 3);
    EXPECT_EQ(png.text.at("Level"), "2");
    EXPECT_EQ(png.text.at("Style"), "hillshade");
    EXPECT_NEAR(std::stod(png.text.at("Maximum height")), 1000.0, 1.0);
    EXPECT_NEAR(std::stod(png.text.at("Minimum height")), r.minimum, 0.0);
    // The summit (the brightest hypsometric colour) is where the hill is: x 100, y 150 of 256.
    size_t brightest = 0;
    int best = -1;
    for (size_t k = 0; k < png.samples.size(); k += 3) {
        const int sum = png.samples[k] + png.samples[k + 1] + png.samples[k + 2];
        if (sum > best) {
            best = sum;
            brightest = k / 3;
        }
    }
    EXPECT_NEAR(static_cast<double>(brightest % 129), 50.0, 3.0);
    EXPECT_NEAR(static_cast<double>(brightest / 129), 128 - 75.0, 3.0);
    // Residuals: their range times the scale; a level that does not exist is refused.
    o.style = PreviewStyle::Residuals;
    o.level = 3;
    const PreviewReport res = writePreview(dem, dir.file("res.png"), o);
    EXPECT_EQ(res.width, 257);
    EXPECT_LT(res.minimum, 0.0);
    EXPECT_GT(res.maximum, 0.0);
    o.level = 9;
    EXPECT_THROW(writePreview(dem, dir.file("none.png"), o), OptionError);
    EXPECT_FALSE(fs::exists(dir.file("none.png")));
    // The program: one line naming the problem, nothing written.
    const test::RunResult bad =
        test::run(test::programPath("pyramid") + " preview " + dem + " -o " + dir.file("x.jpg"));
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("a preview is a PNG"), std::string::npos) << bad.err;
    const test::RunResult ok =
        test::run(test::programPath("pyramid") + " preview -q --json --size 200 " + dem + " -o " + dir.file("cli.png"));
    ASSERT_EQ(ok.exitCode, 0) << ok.err;
    const nlohmann::json report = nlohmann::json::parse(ok.out);
    EXPECT_EQ(report.at("width"), 129);
    EXPECT_EQ(report.at("level"), 2);
}

TEST(Preview, AnOrthoLevelIsItsTilesPixels) {
    TempDir dir;
    test::writeImage(dir.file("in.png"), 128, 128, 3, test::texturedColours(128, 128), false);
    OrthoEncodeOptions o;
    o.levels.tileSize = 32;
    encodeOrtho(dir.file("in.png"), dir.file("out"), o);
    PreviewOptions p;
    p.level = 2;
    for (const std::string file : {"RGB.dat", "residuals/RGB.dat"}) {
        const PreviewReport r = writePreview(dir.file("out/" + file), dir.file("o.png"), p);
        EXPECT_EQ(r.kind, file == "RGB.dat" ? "ortho" : "colour residuals");
        const Png png = readPng(dir.file("o.png"));
        ASSERT_EQ(png.width, 128);
        ASSERT_EQ(png.channels, 3);
        // The plain tiles' finest level is the input, pixel for pixel (lossless tiles); the
        // colour residuals' is what the colour producer rebuilds.
        std::vector<uint16_t> expected = test::texturedColours(128, 128);
        if (file != "RGB.dat") {
            ColourProducer colours(openOrthoSet(dir.file("out/" + file)));
            for (int ty = 0; ty < 4; ++ty) {
                for (int tx = 0; tx < 4; ++tx) {
                    const auto tile = colours.tile(2, tx, ty);
                    for (int j = 0; j < 32; ++j) {
                        for (int i = 0; i < 32; ++i) {
                            for (int c = 0; c < 3; ++c) {
                                const size_t row = static_cast<size_t>(127 - (ty * 32 + j)), col = static_cast<size_t>(tx * 32 + i);
                                expected[(row * 128 + col) * 3 + c] =
                                    (*tile)[(static_cast<size_t>(j + 2) * 36 + static_cast<size_t>(i + 2)) * 3 + c];
                            }
                        }
                    }
                }
            }
        }
        for (size_t k = 0; k < expected.size(); ++k) {
            ASSERT_EQ(png.samples[k] / 257, expected[k]) << file << " sample " << k;
        }
    }
    p.style = PreviewStyle::Hillshade;
    EXPECT_THROW(writePreview(dir.file("out/RGB.dat"), dir.file("h.png"), p), OptionError);
}

// A legend: a colour bar from the lowest value (left) to the highest (right) under the image,
// the rows counted in the PNG's text and the report.
TEST(Preview, ALegendIsTheColourBarOfTheRange) {
    TempDir dir;
    const std::string dem = demOf(dir, "hill", 129, [](double x, double y) { return 10.0 * x - 3.0 * y; });
    PreviewOptions o;
    o.style = PreviewStyle::Heights;
    o.legend = true;
    for (const PreviewStyle style : {PreviewStyle::Heights, PreviewStyle::Residuals}) {
        o.style = style;
        const PreviewReport r = writePreview(dem, dir.file("legend.png"), o);
        ASSERT_GT(r.legendHeight, 10);
        const Png png = readPng(dir.file("legend.png"));
        ASSERT_EQ(png.width, 129);
        ASSERT_EQ(png.height, 129 + r.legendHeight);
        EXPECT_EQ(png.text.at("Legend rows"), std::to_string(r.legendHeight));
        // The bar: 4 pixels in from each side, 4 rows below the image (scale 1 under 240 pixels).
        const auto pixel = [&](int x, int y) {
            const size_t k = (static_cast<size_t>(y) * png.width + static_cast<size_t>(x)) * 3;
            return Rgb8{static_cast<uint8_t>(png.samples[k] / 257), static_cast<uint8_t>(png.samples[k + 1] / 257),
                        static_cast<uint8_t>(png.samples[k + 2] / 257)};
        };
        const int bar = 129 + 5;
        if (style == PreviewStyle::Heights) {
            EXPECT_EQ(pixel(4, bar), hypsometricColour(0.0));
            EXPECT_EQ(pixel(124, bar), hypsometricColour(1.0));
        } else {
            EXPECT_EQ(pixel(4, bar), divergingColour(-1.0));
            EXPECT_EQ(pixel(124, bar), divergingColour(1.0));
            EXPECT_EQ(pixel(64, bar), divergingColour(0.0));
        }
    }
    o.style = PreviewStyle::Shade;
    EXPECT_THROW(writePreview(dem, dir.file("none.png"), o), OptionError);
}

} // namespace
} // namespace pyramid
