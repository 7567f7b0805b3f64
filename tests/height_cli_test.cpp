// `pyramid height`: the reconstructed height at a point lands where the source has it. A planar
// file built sample for sample from its input gives each input pixel's height (within the
// quantization bound) by --pixel and by --grid; a spherical set built from a map whose height
// is a smooth function of longitude and latitude gives that function at points on every face
// by --lonlat.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::programPath;
using test::run;

std::string quoted(const std::string& s) { return "'" + s + "'"; }

double heightOf(const std::string& args) {
    const auto r = run(programPath("pyramid") + " height " + args + " --json");
    EXPECT_EQ(r.exitCode, 0) << args << "\n" << r.err;
    return r.exitCode == 0 ? nlohmann::json::parse(r.out)["height"].get<double>() : NAN;
}

TEST(HeightCli, PlanarPixelsAndGridPointsGiveTheSourceHeights) {
    test::TempDir dir;
    const int side = 65; // 4 << 4 intervals: the finest grid is the input, sample for sample
    const std::vector<float> heights = test::syntheticHeights(side, side, 900.0f);
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, side, side, heights);
    const std::string file = dir.file("DEM.dat");
    const auto built = run(programPath("preprocessDem") + " -q " + quoted(input) + " -o " + quoted(file) +
                           " --tile-size 16 --root-tile-size 4 --scale 0.5");
    ASSERT_EQ(built.exitCode, 0) << built.err;
    for (const auto& [x, y] : {std::pair{0, 0}, {64, 64}, {17, 40}, {64, 3}, {31, 0}}) {
        const double want = heights[static_cast<size_t>(y) * side + static_cast<size_t>(x)];
        SCOPED_TRACE("pixel " + std::to_string(x) + "," + std::to_string(y));
        EXPECT_NEAR(heightOf(quoted(file) + " --pixel " + std::to_string(x) + "," + std::to_string(y) + " --source " +
                             quoted(input)),
                    want, 0.25 + 1e-3);
        // The same sample on the grid: x east, y north from the south-west corner.
        EXPECT_NEAR(heightOf(quoted(file) + " --grid " + std::to_string(x) + "," + std::to_string(64 - y)), want,
                    0.25 + 1e-3);
    }
    // Half-way between two samples: their mean, as the producer's tiles give them.
    const double a = heightOf(quoted(file) + " --grid 10,20"), b = heightOf(quoted(file) + " --grid 11,20");
    EXPECT_NEAR(heightOf(quoted(file) + " --grid 10.5,20"), (a + b) / 2, 1e-6);
    // Outside the root quad: one line, exit 1; without a point: a usage error, exit 2.
    auto r = run(programPath("pyramid") + " height " + quoted(file) + " --grid 65,3");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("outside the root quad"), std::string::npos) << r.err;
    r = run(programPath("pyramid") + " height " + quoted(file));
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("the point (--grid X,Y"), std::string::npos) << r.err;
}

// A planar file built from a georeferenced input takes points in the input's CRS (and, for a
// geographic one, as longitude and latitude), placed by the sidecar beside it: the real SRTM
// tile's pixel centres give the heights of those pixels, and its summit is where it should be.
TEST(HeightCli, PlanarFilesOfGeoreferencedInputsTakeCrsPoints) {
    const std::string rainier = test::sharedFixturePath("inputs/mt_rainier_90m.tif");
    if (rainier.empty()) {
        GTEST_SKIP() << "../shared/fixtures/inputs/mt_rainier_90m.tif is not there";
    }
    test::TempDir dir;
    const std::string file = dir.file("rainier.dat");
    // 1201 samples: 150 << 3 intervals, the input sample for sample.
    const auto built = run(programPath("preprocessDem") + " -q " + quoted(rainier) + " -o " + quoted(file) +
                           " --tile-size 150 --root-tile-size 150");
    ASSERT_EQ(built.exitCode, 0) << built.err;
    // Pixel (X, Y)'s centre: 1/1200 degree pixels from 122 W, 47 N (the file's PixelIsArea
    // corner lies half a pixel beyond).
    for (const auto& [x, y] : {std::pair{0, 0}, {600, 600}, {1200, 1200}, {287, 918}, {1199, 2}}) {
        SCOPED_TRACE("pixel " + std::to_string(x) + "," + std::to_string(y));
        char lonlat[64];
        std::snprintf(lonlat, sizeof lonlat, "%.12f,%.12f", -122.0 + x / 1200.0, 47.0 - y / 1200.0);
        const double byPixel = heightOf(quoted(file) + " --pixel " + std::to_string(x) + "," + std::to_string(y) +
                                        " --source " + quoted(rainier));
        EXPECT_NEAR(heightOf(quoted(file) + " --lonlat " + lonlat), byPixel, 1e-6);
        EXPECT_NEAR(heightOf(quoted(file) + " --xy " + lonlat), byPixel, 1e-6);
    }
    // Mount Rainier's summit (4392 m; 90 m samples round it down a little).
    const double summit = heightOf(quoted(file) + " --lonlat -121.7603,46.8528");
    EXPECT_GT(summit, 4150.0);
    EXPECT_LT(summit, 4400.0);
    // A file of an input without georeferencing has no sidecar: one line, exit 1.
    const std::string plain = dir.file("plain.tif");
    test::writeFloatRaster(plain, 33, 33, test::syntheticHeights(33, 33));
    ASSERT_EQ(run(programPath("preprocessDem") + " -q " + quoted(plain) + " -o " + quoted(dir.file("plain.dat")) +
                  " --tile-size 8 --root-tile-size 4")
                  .exitCode,
              0);
    const auto r = run(programPath("pyramid") + " height " + quoted(dir.file("plain.dat")) + " --xy 3,4");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("not built from a georeferenced input"), std::string::npos) << r.err;
}

// --pixel takes the raster's samples alone (an index beyond them is refused), north-up as the
// encoder reads it (a south-up copy of the same ground gives the same heights), and a georeferenced
// source must put the pixel where the build did: another raster of other ground, or --stretch
// where the build had none, is refused rather than answered from the wrong place.
TEST(HeightCli, PixelsOfAGeoreferencedSourceMustLieWhereTheBuildPutThem) {
    test::TempDir dir;
    const int w = 65, h = 33; // 64 intervals across: without --stretch the raster fills the upper half
    const std::vector<float> heights = test::syntheticHeights(w, h, 900.0f);
    const double step = 1.0 / 64.0;
    const std::string input = dir.file("dem.tif");
    test::writeGeoTiff(input, w, h, heights, test::geographicTags(4326, 7.0, 46.5, step));
    const std::string file = dir.file("DEM.dat");
    const auto built = run(programPath("preprocessDem") + " -q " + quoted(input) + " -o " + quoted(file) +
                           " --tile-size 16 --root-tile-size 4 --scale 0.5");
    ASSERT_EQ(built.exitCode, 0) << built.err;
    const std::string pixel = " --pixel 17,9 --source ";
    const double want = heights[9 * w + 17];
    EXPECT_NEAR(heightOf(quoted(file) + pixel + quoted(input)), want, 0.25 + 1e-3);

    // The same ground south-up (rows running north): pixel 17,9 counted from the north is the same sample.
    std::vector<float> mirrored(heights.size());
    for (int y = 0; y < h; ++y) {
        std::copy_n(heights.begin() + static_cast<std::ptrdiff_t>(y) * w, w,
                    mirrored.begin() + static_cast<std::ptrdiff_t>(h - 1 - y) * w);
    }
    test::GeoTiffTags southUp;
    southUp.shortKeys = test::geographicTags(4326, 7.0, 46.5, step).shortKeys;
    test::setTransformation(southUp, {7.0, step, 0.0, 46.5 - h * step, 0.0, step});
    const std::string flipped = dir.file("south-up.tif");
    test::writeGeoTiff(flipped, w, h, mirrored, southUp);
    EXPECT_NEAR(heightOf(quoted(file) + pixel + quoted(flipped)), want, 0.25 + 1e-3);

    const auto refused = [&](const std::string& args, const std::string& message) {
        const auto r = run(programPath("pyramid") + " height " + quoted(file) + args);
        EXPECT_EQ(r.exitCode, 1) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
        EXPECT_EQ(r.out, "") << args;
    };
    // The same samples a pixel to the east: other ground.
    const std::string shifted = dir.file("shifted.tif");
    test::writeGeoTiff(shifted, w, h, heights, test::geographicTags(4326, 7.0 + step, 46.5, step));
    refused(pixel + quoted(shifted), "not the raster the file was built from alone");
    // --stretch, which the build did not have, places rows elsewhere.
    refused(pixel + quoted(input) + " --stretch", "the build's geometry with --stretch");
    // Beyond the samples (inside the root quad, whose lower half the raster does not reach).
    refused(" --pixel 17,33 --source " + quoted(input), "17,33 is outside");
    refused(" --pixel=-1,0 --source " + quoted(input), "columns 0..64, rows 0..32");
}

double smoothHeight(double lon, double lat) {
    constexpr double kDegree = 3.14159265358979323846 / 180.0;
    return 1000.0 + 10.0 * lat + 300.0 * std::sin(lon * kDegree) + 200.0 * std::cos(lon * kDegree);
}

TEST(HeightCli, LongitudeAndLatitudeLandOnTheRightFace) {
    test::TempDir dir;
    const int w = 720, h = 360; // half-degree pixels, centres at -179.75.. and 89.75..
    std::vector<float> map(static_cast<size_t>(w) * h);
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            map[static_cast<size_t>(j) * w + static_cast<size_t>(i)] =
                static_cast<float>(smoothHeight(-180.0 + (i + 0.5) * 0.5, 90.0 - (j + 0.5) * 0.5));
        }
    }
    const std::string input = dir.file("map.tif");
    test::writeFloatRaster(input, w, h, map);
    const std::string set = dir.file("planet");
    const auto built = run(programPath("preprocessSphericalDem") + " -q " + quoted(input) + " -o " + quoted(set) +
                           " --tile-size 32 --root-tile-size 8 --scale 0.5");
    ASSERT_EQ(built.exitCode, 0) << built.err;
    struct Point {
        double lon, lat;
        int face;
    };
    // Points away from the faces' centre lines, so that a sign or axis mistaken in the face
    // table moves them.
    for (const Point& p : {Point{20, 15, 3}, Point{70, 10, 4}, Point{-110, -10, 2}, Point{170, 5, 5},
                           Point{-160, -20, 5}, Point{45, 70, 1}, Point{-120, -65, 6}, Point{-30, -30, 3}}) {
        SCOPED_TRACE(std::to_string(p.lon) + "," + std::to_string(p.lat));
        const std::string where = std::to_string(p.lon) + "," + std::to_string(p.lat);
        const auto r = run(programPath("pyramid") + " height " + quoted(set) + " --lonlat " + where + " --json");
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const nlohmann::json j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["face"], p.face);
        // Quantization (0.25), the map's bilinear resampling and the face grid's (about 0.1 m
        // each for this smooth field).
        EXPECT_NEAR(j["height"].get<double>(), smoothHeight(p.lon, p.lat), 1.0);
    }
}

} // namespace
} // namespace pyramid
