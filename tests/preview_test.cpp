// Previews (`pyramid preview`, libpyramid/preview/) and DEM tiles as PNG (`pyramid tile -o
// x.png`): a tilted plane's hillshade is uniform and a cone's is not; the PNG has the level's
// size and its range in its text; an ortho level's preview is its tiles' pixels; a DEM tile's
// 16-bit PNG reads back to its elevations within the quantization of its range.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/preview/preview.hpp"
#include "libpyramid/preview/shading.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

struct Png {
    int width = 0, height = 0, channels = 0, depth = 0;
    std::map<std::string, std::string> text;
    std::vector<uint16_t> samples; // row 0 = top
};

// Reads the PNG's pixels (OpenImageIO) and its tEXt chunks (read here, byte by byte).
Png readPng(const std::string& path) {
    Png png;
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path;
    if (!in) {
        return png;
    }
    const OIIO::ImageSpec& spec = in->spec();
    png.width = spec.width;
    png.height = spec.height;
    png.channels = spec.nchannels;
    png.depth = static_cast<int>(spec.format.size()) * 8;
    png.samples.resize(static_cast<size_t>(png.width) * png.height * png.channels);
    EXPECT_TRUE(in->read_image(0, 0, 0, png.channels, OIIO::TypeDesc::UINT16, png.samples.data()));
    in->close();
    std::ifstream file(path, std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
    for (size_t at = 8; at + 12 <= bytes.size();) {
        const uint32_t n = (uint32_t{bytes[at]} << 24) | (uint32_t{bytes[at + 1]} << 16) |
                           (uint32_t{bytes[at + 2]} << 8) | bytes[at + 3];
        const std::string type(bytes.begin() + static_cast<long>(at) + 4, bytes.begin() + static_cast<long>(at) + 8);
        if (type == "tEXt") {
            const std::string chunk(bytes.begin() + static_cast<long>(at) + 8,
                                    bytes.begin() + static_cast<long>(at) + 8 + n);
            const size_t zero = chunk.find('\0');
            png.text[chunk.substr(0, zero)] = chunk.substr(zero + 1);
        }
        at += 12 + n;
    }
    return png;
}

// A DEM of `w` x `w` samples from f(x, y) (x east, y north, in samples).
std::string demOf(const TempDir& dir, const std::string& name, int w, double (*f)(double, double)) {
    std::vector<float> v(static_cast<size_t>(w) * w);
    for (int row = 0; row < w; ++row) {
        for (int x = 0; x < w; ++x) {
            v[static_cast<size_t>(row) * w + x] = static_cast<float>(f(x, w - 1 - row));
        }
    }
    test::writeFloatRaster(dir.file(name + ".tif"), w, w, v);
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 32;
    o.autoScale = true;
    encodeDem(dir.file(name + ".tif"), dir.file(name + ".dat"), o);
    return dir.file(name + ".dat");
}

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

} // namespace
} // namespace pyramid
