// Previews of planets (`pyramid preview`, libpyramid/preview/planet_preview.hpp): the world map of
// a DEM planet shows water exactly where its map has sea, an ortho planet's world map is its map
// resampled and its cube cross is each face's own preview; region files are not taken for a
// planet's faces.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"
#include "libpyramid/preview/preview.hpp"
#include "libpyramid/preview/preview_levels.hpp"
#include "libpyramid/preview/shading.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/preview_pngs.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::Png;
using test::readPng;
using test::TempDir;
using preview::ElevationPaint;

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

} // namespace
} // namespace pyramid
