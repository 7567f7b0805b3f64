// Previews (`pyramid preview`, libpyramid/preview/) and DEM tiles as PNG (`pyramid tile -o
// x.png`): a tilted plane's hillshade is uniform and a cone's is not; the PNG has the level's
// size and its range in its text; an ortho level's preview is its tiles' pixels; a DEM tile's
// 16-bit PNG reads back to its elevations within the quantization of its range.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
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
#include "formats/pyramid_set.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/preview/preview.hpp"
#include "libpyramid/preview/preview_levels.hpp"
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
using preview::ElevationPaint;

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

// A global map's channel (OpenImageIO), row 0 the north.
struct Map {
    int width = 0, height = 0, channels = 0;
    std::vector<uint8_t> pixels;
    int at(int64_t x, int64_t y, int c) const {
        x = ((x % width) + width) % width; // around the globe
        y = std::clamp<int64_t>(y, 0, height - 1);
        return pixels[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) * channels + c];
    }
    // The pixel whose centre is nearest (longitude, latitude), in degrees.
    std::array<int64_t, 2> pixelOf(double longitude, double latitude) const {
        return {static_cast<int64_t>(std::floor((longitude + 180.0) / 360.0 * width)),
                static_cast<int64_t>(std::floor((90.0 - latitude) / 180.0 * height))};
    }
};

Map readMap(const std::string& path) {
    Map m;
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path;
    m.width = in->spec().width;
    m.height = in->spec().height;
    m.channels = in->spec().nchannels;
    m.pixels.resize(static_cast<size_t>(m.width) * m.height * m.channels);
    EXPECT_TRUE(in->read_image(0, 0, 0, m.channels, OIIO::TypeDesc::UINT8, m.pixels.data()));
    return m;
}

// The centre of pixel (c, r) of an equirectangular image of width x height.
double longitudeOf(int c, int width) { return -180.0 + (c + 0.5) * 360.0 / width; }
double latitudeOf(int r, int height) { return 90.0 - (r + 0.5) * 180.0 / height; }

// On the spherical pyramids built from the global map, the world map shows water exactly where
// the map has sea, land where it has land (away from coasts: 3 map pixels of ground either way).
TEST(Preview, APlanetsWorldMapShowsLandWhereItsMapHasIt) {
    TempDir dir;
    const Map srtm = readMap(test::samplePath("srtm.png"));
    ASSERT_EQ(srtm.width, 1350);
    // The sea: the map's most common red value, give or take 1 (its floor is not flat).
    std::vector<int64_t> counts(256, 0);
    for (int y = 0; y < srtm.height; ++y) {
        for (int x = 0; x < srtm.width; ++x) {
            ++counts[static_cast<size_t>(srtm.at(x, y, 0))];
        }
    }
    const int sea = static_cast<int>(std::max_element(counts.begin(), counts.end()) - counts.begin());
    ASSERT_EQ(test::run(test::programPath("preprocessSphericalDem") + " " + test::samplePath("srtm.png") +
                        " --height-scale 10000/255 --tile-size 32 --root-tile-size 8 -q -o " + dir.file("planet"))
                  .exitCode,
              0);
    PreviewOptions o;
    o.style = PreviewStyle::Heights;
    o.size = 720; // faces of at most 180 samples: level 4, 129
    o.seaLevel = (sea + 1) * 10000.0 / 255.0 + 1.0; // the sea reconstructs within the scale (1) of its heights
    const PreviewReport r = writePreview(dir.file("planet"), dir.file("world.png"), o);
    EXPECT_EQ(r.projection, "equirectangular");
    EXPECT_EQ(r.level, 4);
    ASSERT_EQ(r.faces.size(), 6u);
    EXPECT_EQ(r.faces[2], dir.file("planet/DEM3.dat"));
    const Png png = readPng(dir.file("world.png"));
    ASSERT_EQ(png.width, 512);
    ASSERT_EQ(png.height, 256);
    EXPECT_EQ(png.text.at("Projection"), "equirectangular");
    const Rgb8 water = ElevationPaint(PreviewStyle::Heights, 0, 1, o).base(-1.0);
    int64_t seaPixels = 0, landPixels = 0;
    for (int y = 0; y < png.height; ++y) {
        for (int x = 0; x < png.width; ++x) {
            const auto [mx, my] = srtm.pixelOf(longitudeOf(x, png.width), latitudeOf(y, png.height));
            bool allSea = true, allLand = true;
            // 3 map pixels of ground either way: more pixels of longitude towards the poles.
            const double across = 3.0 / std::max(std::cos(latitudeOf(y, png.height) * M_PI / 180.0), 0.01);
            const auto reach = static_cast<int64_t>(std::min(std::ceil(across), srtm.width / 2.0));
            for (int64_t dy = -3; dy <= 3; ++dy) {
                for (int64_t dx = -reach; dx <= reach; ++dx) {
                    const int red = srtm.at(mx + dx, my + dy, 0);
                    allSea = allSea && red <= sea + 1;
                    allLand = allLand && red >= sea + 10;
                }
            }
            const size_t k = (static_cast<size_t>(y) * png.width + x) * 3;
            const bool drawnWater = png.samples[k] / 257 == water[0] && png.samples[k + 1] / 257 == water[1] &&
                                    png.samples[k + 2] / 257 == water[2];
            if (allSea) {
                ++seaPixels;
                ASSERT_TRUE(drawnWater) << "sea at pixel " << x << "," << y;
            } else if (allLand) {
                ++landPixels;
                ASSERT_FALSE(drawnWater) << "land at pixel " << x << "," << y;
            }
        }
    }
    EXPECT_GT(seaPixels, png.width * png.height / 2);
    EXPECT_GT(landPixels, png.width * png.height / 10);
}

// The world map of an ortho planet is its map, resampled: close to the map at the same place,
// far from it 10 degrees away. The cube cross is each face's own preview, pixel for pixel, and
// nothing where no face is.
TEST(Preview, APlanetsOrthoWorldMapAndCubeCross) {
    TempDir dir;
    ASSERT_EQ(test::run(test::programPath("preprocessSphericalOrtho") + " " + test::samplePath("bluemarble.png") +
                        " --tile-size 32 --outputs tiff -q -o " + dir.file("planet"))
                  .exitCode,
              0);
    const Map map = readMap(test::samplePath("bluemarble.png"));
    PreviewOptions o;
    o.level = 2; // faces of 128 pixels: a world map of 512 x 256
    const PreviewReport world = writePreview(dir.file("planet"), dir.file("world.png"), o);
    EXPECT_EQ(world.kind, "ortho");
    const Png png = readPng(dir.file("world.png"));
    ASSERT_EQ(png.width, 512);
    ASSERT_EQ(png.height, 256);
    ASSERT_EQ(png.channels, 3);
    double here = 0.0, shifted = 0.0;
    for (int y = 0; y < png.height; ++y) {
        for (int x = 0; x < png.width; ++x) {
            const auto [mx, my] = map.pixelOf(longitudeOf(x, png.width), latitudeOf(y, png.height));
            const auto [sx, sy] = map.pixelOf(longitudeOf(x, png.width) + 10.0, latitudeOf(y, png.height));
            for (int c = 0; c < 3; ++c) {
                const int got = png.samples[(static_cast<size_t>(y) * png.width + x) * 3 + c] / 257;
                here += std::abs(got - map.at(mx, my, c));
                shifted += std::abs(got - map.at(sx, sy, c));
            }
        }
    }
    const double samples = png.width * png.height * 3.0;
    EXPECT_LT(here / samples, 8.0);
    EXPECT_GT(shifted / samples, 2.0 * here / samples);

    o.projection = PreviewProjection::Cube;
    const PreviewReport cube = writePreview(dir.file("planet/RGB4.dat"), dir.file("cube.png"), o);
    EXPECT_EQ(cube.projection, "cube");
    const Png cross = readPng(dir.file("cube.png"));
    ASSERT_EQ(cross.width, 512);
    ASSERT_EQ(cross.height, 384);
    const int cells[3][4] = {{1, 0, 0, 0}, {2, 3, 4, 5}, {6, 0, 0, 0}};
    o.projection = PreviewProjection::Face;
    for (int band = 0; band < 3; ++band) {
        for (int column = 0; column < 4; ++column) {
            const int face = cells[band][column];
            Png alone;
            if (face) {
                writePreview(dir.file("planet/RGB" + std::to_string(face) + ".dat"), dir.file("face.png"), o);
                alone = readPng(dir.file("face.png"));
                ASSERT_EQ(alone.width, 128);
            }
            for (int y = 0; y < 128; ++y) {
                for (int x = 0; x < 128 * 3; ++x) {
                    const uint16_t got = cross.samples[static_cast<size_t>(band * 128 + y) * 512 * 3 +
                                                       static_cast<size_t>(column * 128 * 3 + x)];
                    const uint16_t want = face ? alone.samples[static_cast<size_t>(y) * 128 * 3 + static_cast<size_t>(x)] : 0;
                    ASSERT_EQ(got, want) << "face " << face << " at " << x / 3 << "," << y;
                }
            }
        }
    }
    // The program: the report names the projection, the faces and the body; a directory of two
    // planets is refused, naming both.
    const std::string preview = test::programPath("pyramid") + " preview -q --size 256 ";
    const test::RunResult ok = test::run(preview + dir.file("planet") + " --report - -o " + dir.file("p.png"));
    ASSERT_EQ(ok.exitCode, 0) << ok.err;
    const nlohmann::json report = nlohmann::json::parse(ok.out);
    EXPECT_EQ(report.at("projection"), "equirectangular");
    EXPECT_EQ(report.at("width"), 256);
    EXPECT_EQ(report.at("faces").size(), 6u);
    EXPECT_EQ(report.at("body").get<std::string>().rfind("wgs84: ellipsoid", 0), 0u) << report.at("body");
    for (int f = 1; f <= 6; ++f) {
        fs::copy_file(dir.file("planet/RGB" + std::to_string(f) + ".dat"), dir.file("planet/ALT" + std::to_string(f) + ".dat"));
    }
    const test::RunResult two = test::run(preview + dir.file("planet") + " -o " + dir.file("two.png"));
    EXPECT_EQ(two.exitCode, 1);
    EXPECT_NE(two.err.find("holds several planets (ALT1..6.dat, RGB1..6.dat)"), std::string::npos) << two.err;
    EXPECT_FALSE(fs::exists(dir.file("two.png")));
    // A face file of an incomplete family is refused with nothing written.
    fs::remove(dir.file("planet/RGB6.dat"));
    o.projection = PreviewProjection::Equirectangular;
    EXPECT_THROW(writePreview(dir.file("planet/RGB1.dat"), dir.file("none.png"), o), Error);
    EXPECT_FALSE(fs::exists(dir.file("none.png")));
}

// Region files (NAME-L<level>-<tx>-<ty>.dat, formats/pyramid_set.hpp) are not cube faces, though
// six of them may end in 1..6.dat: a region set's directory is drawn as the set, and a planet
// whose faces are sets as the planet.
TEST(Preview, RegionFilesAreNotTakenForAPlanetsFaces) {
    TempDir dir;
    const std::string input = " " + test::samplePath("bluemarble.png") + " --tile-size 64 -q -o ";
    ASSERT_EQ(test::run(test::programPath("preprocessOrtho") + input + dir.file("flat") +
                        " --outputs residuals --max-file-bytes 200K")
                  .exitCode,
              0);
    ASSERT_EQ(test::run(test::programPath("preprocessSphericalOrtho") + input + dir.file("planet") +
                        " --outputs tiff --max-file-bytes 40K")
                  .exitCode,
              0);
    // What made them look like planets: six region files RGB-L4-0-1.dat .. RGB-L4-0-6.dat, and
    // so for a face.
    for (int k = 1; k <= 6; ++k) {
        ASSERT_TRUE(fs::exists(regionFilePath(dir.file("flat/residuals/RGB.dat"), {4, 0, k})));
        ASSERT_TRUE(fs::exists(regionFilePath(dir.file("planet/RGB5.dat"), {3, 0, k})));
    }
    PreviewOptions o;
    o.level = 2;
    const PreviewReport set = writePreview(dir.file("flat/residuals"), dir.file("set.png"), o);
    EXPECT_EQ(set.kind, "colour residuals");
    EXPECT_EQ(set.projection, "face");
    writePreview(dir.file("flat/residuals/RGB.dat"), dir.file("main.png"), o);
    const Png fromDirectory = readPng(dir.file("set.png")), fromMain = readPng(dir.file("main.png"));
    EXPECT_EQ(fromDirectory.width, 256);
    EXPECT_EQ(fromDirectory.samples, fromMain.samples);

    const PreviewReport planet = writePreview(dir.file("planet"), dir.file("planet.png"), o);
    EXPECT_EQ(planet.projection, "equirectangular");
    EXPECT_EQ(planet.width, 1024); // faces of 256 pixels at level 2
    // A region file named as one face of a planet is not one.
    o.projection = PreviewProjection::Equirectangular;
    EXPECT_THROW(writePreview(regionFilePath(dir.file("planet/RGB5.dat"), {3, 0, 1}), dir.file("r.png"), o), Error);
    EXPECT_FALSE(fs::exists(dir.file("r.png")));
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
