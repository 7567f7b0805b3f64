// preprocessDem and preprocessOrtho carry a georeferenced input's placement: the report's
// `georeference` object and the sidecar beside the output give the CRS, the root quad's and the
// data's ground extent and the CRS units between samples at every level; the pyramid itself is
// the one an unreferenced input with the same pixels makes (a south-up input's, that of its
// north-up copy), and unreferenced inputs get no sidecar.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/runtime/height_query.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"
#include "tests/support/small_dem.hpp"

namespace pyramid {
namespace {

TEST(PlanarGeoreference, DemReportAndSidecar) {
    test::TempDir dir;
    // 65 x 65 samples in UTM 10N, 30 m apart: the finest grid of 64 intervals, sample for sample.
    const double x0 = 590000, y0 = 5190000, step = 30;
    const std::vector<float> heights = test::syntheticHeights(65, 65);
    test::writeGeoTiff(dir.file("utm.tif"), 65, 65, heights, test::projectedTags(32610, x0, y0, step));
    test::writeFloatRaster(dir.file("plain.tif"), 65, 65, heights);
    DemEncodeOptions o = test::smallDemOptions();
    const DemReport r = encodeDem(dir.file("utm.tif"), dir.file("utm.dat"), o);
    ASSERT_TRUE(r.georeference.has_value());
    const PyramidGeoreference& g = *r.georeference;
    EXPECT_EQ(g.crs.crsText(), "EPSG:32610 (WGS 84 / UTM zone 10N)");
    // Vertices: the root quad runs from the first sample's centre to the last one's.
    const std::array<double, 4> root{x0 + 15, y0 - 64 * 30 - 15, x0 + 64 * 30 + 15, y0 - 15};
    EXPECT_EQ(g.rootExtent, root);
    const std::array<double, 4> data{x0, y0 - 65 * 30, x0 + 65 * 30, y0};
    EXPECT_EQ(g.dataExtent, data);
    ASSERT_EQ(g.unitsPerSample.size(), 4u);
    EXPECT_DOUBLE_EQ(g.unitsPerSample[3][0], 30.0);
    EXPECT_DOUBLE_EQ(g.unitsPerSample[3][1], 30.0);
    EXPECT_DOUBLE_EQ(g.unitsPerSample[0][0], 240.0); // 8 intervals across the root

    const nlohmann::json report = toJson(r);
    EXPECT_EQ(report["georeference"]["crs"]["epsg"], 32610);
    EXPECT_EQ(report["georeference"]["crs"]["projection"], "transverse Mercator");
    EXPECT_EQ(report["georeference"]["root_extent"]["min_x"], x0 + 15);
    const nlohmann::json sidecar = nlohmann::json::parse(test::readFile(dir.file("utm.dat.georef.json")));
    EXPECT_EQ(sidecar["pyramid"], "utm.dat");
    EXPECT_EQ(sidecar["root_extent"], report["georeference"]["root_extent"]);
    EXPECT_EQ(sidecar["units_per_sample"], report["georeference"]["units_per_sample"]);

    // The same pixels without georeferencing: the same pyramid, no sidecar, a null object.
    const DemReport plain = encodeDem(dir.file("plain.tif"), dir.file("plain.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("plain.dat")), test::readFile(dir.file("utm.dat")));
    EXPECT_FALSE(plain.georeference.has_value());
    EXPECT_TRUE(toJson(plain)["georeference"].is_null());
    EXPECT_FALSE(std::filesystem::exists(dir.file("plain.dat.georef.json")));
}

TEST(PlanarGeoreference, OrthoReportAndSidecar) {
    test::TempDir dir;
    // 100 x 60 pixels of 0.01 degree, aspect kept: the root quad is the 100-pixel square at the
    // north-west corner.
    std::vector<uint8_t> rgb(100 * 60 * 3);
    for (size_t k = 0; k < rgb.size(); ++k) {
        rgb[k] = static_cast<uint8_t>(k * 7);
    }
    test::writeGeoTiffRgb(dir.file("img.tif"), 100, 60, rgb, test::geographicTags(4326, 10.0, 50.0, 0.01));
    OrthoEncodeOptions o;
    o.levels.tileSize = 16;
    const OrthoReport r = encodeOrtho(dir.file("img.tif"), dir.file("out"), o);
    ASSERT_TRUE(r.georeference.has_value());
    const PyramidGeoreference& g = *r.georeference;
    EXPECT_EQ(r.maxLevel, 3); // 128 pixels hold 100
    EXPECT_NEAR(g.rootExtent[0], 10.0, 1e-12);
    EXPECT_NEAR(g.rootExtent[1], 49.0, 1e-12);
    EXPECT_NEAR(g.rootExtent[2], 11.0, 1e-12);
    EXPECT_NEAR(g.rootExtent[3], 50.0, 1e-12);
    EXPECT_NEAR(g.dataExtent[1], 49.4, 1e-12);
    EXPECT_NEAR(g.unitsPerSample[3][0], 1.0 / 128, 1e-15);
    EXPECT_NEAR(g.unitsPerSample[0][1], 1.0 / 16, 1e-15);
    const nlohmann::json sidecar = nlohmann::json::parse(test::readFile(dir.file("out") + "/RGB.dat.georef.json"));
    EXPECT_EQ(sidecar["crs"]["epsg"], 4326);
    EXPECT_EQ(sidecar["samples"], "pixel centres");
    EXPECT_EQ(sidecar["pyramid"], "RGB.dat");
}

// Longitude and latitude find the same place on a pyramid whose input counts them in grads from
// the Paris meridian (EPSG:4807, NTF Paris) as on one whose input counts degrees from Greenwich.
TEST(PlanarGeoreference, LonLatOfGradsFromParis) {
    test::TempDir dir;
    const int W = 40, H = 30;
    std::vector<float> heights(static_cast<size_t>(W * H));
    for (size_t k = 0; k < heights.size(); ++k) {
        heights[k] = static_cast<float>(k % 97);
    }
    const double west = 3.0, north = 46.0, step = 1.0 / 64.0, paris = 2.33722917, grad = 0.9;
    test::writeGeoTiff(dir.file("degrees.tif"), W, H, heights, test::geographicTags(4326, west, north, step));
    test::writeGeoTiff(dir.file("grads.tif"), W, H, heights,
                       test::geographicTags(4807, (west - paris) / grad, north / grad, step / grad));
    DemEncodeOptions o;
    o.tileSize = 16;
    o.rootTileSize = 4;
    encodeDem(dir.file("degrees.tif"), dir.file("degrees.dat"), o);
    encodeDem(dir.file("grads.tif"), dir.file("grads.dat"), o);
    for (const auto& [lon, lat] : {std::pair{3.1, 45.9}, std::pair{3.5, 45.7}, std::pair{3.01, 45.55}}) {
        const auto a = crsToRootQuad(dir.file("degrees.dat"), lon, lat, true);
        const auto b = crsToRootQuad(dir.file("grads.dat"), lon, lat, true);
        EXPECT_NEAR(a[0], b[0], 1e-6) << lon << "," << lat;
        EXPECT_NEAR(a[1], b[1], 1e-6) << lon << "," << lat;
        EXPECT_GT(a[0], 0.0);
        EXPECT_LT(a[0], 1.0);
    }
}

// The rows and columns of a W x H raster of `values` values a pixel, mirrored as asked.
template <typename T>
std::vector<T> mirrored(const std::vector<T>& v, int W, int H, int values, bool acrossX, bool acrossY) {
    std::vector<T> out(v.size());
    const auto n = static_cast<size_t>(values);
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) {
            const auto to = static_cast<size_t>((acrossY ? H - 1 - y : y) * W + (acrossX ? W - 1 - x : x));
            std::copy_n(&v[static_cast<size_t>(y * W + x) * n], n, &out[to * n]);
        }
    }
    return out;
}

// A south-up file (row 0 the south edge: a positive north-south pixel size), or one turned half
// round (its columns also run west), is read north-up by preprocessDem and preprocessOrtho
// (sphere/planar_mosaic.hpp): the pyramid and the sidecar of its north-up copy, byte for byte, and
// a sample named by its own column and row.
TEST(PlanarGeoreference, SouthUpInputsMakeTheNorthUpPyramid) {
    test::TempDir dir;
    // 65 x 41 samples: 64 intervals across the finest grid, sample for sample; corners exact in binary.
    const int W = 65, H = 41;
    const double west = 10.0, north = 50.0, step = 1.0 / 64;
    const std::array<double, 6> southUp{west, step, 0.0, north - H * step, 0.0, step};
    const std::array<double, 6> halfRound{west + W * step, -step, 0.0, north - H * step, 0.0, step};
    const std::vector<float> heights = test::syntheticHeights(W, H);
    std::vector<uint8_t> rgb(static_cast<size_t>(W * H * 3));
    for (size_t k = 0; k < rgb.size(); ++k) {
        rgb[k] = static_cast<uint8_t>(k * 7 + k / 97);
    }
    test::writeGeoTiff(dir.file("north.tif"), W, H, heights, test::geographicTags(4326, west, north, step));
    test::writeGeoTiffRgb(dir.file("north-rgb.tif"), W, H, rgb, test::geographicTags(4326, west, north, step));
    DemEncodeOptions o;
    o.tileSize = 16;
    o.rootTileSize = 4;
    encodeDem(dir.file("north.tif"), dir.file("north.dat"), o);
    OrthoEncodeOptions oo;
    oo.levels.tileSize = 16;
    encodeOrtho(dir.file("north-rgb.tif"), dir.file("north-rgb"), oo);
    nlohmann::json sidecar = nlohmann::json::parse(test::readFile(dir.file("north.dat.georef.json")));
    sidecar.erase("pyramid");
    for (const auto& [name, t, acrossX] :
         {std::tuple{"south", southUp, false}, std::tuple{"turned", halfRound, true}}) {
        SCOPED_TRACE(name);
        const std::string dem = dir.file(std::string(name) + ".tif"), image = dir.file(std::string(name) + "-rgb.tif");
        test::GeoTiffTags tags = test::geographicTags(4326, west, north, step);
        test::setTransformation(tags, t);
        test::writeGeoTiff(dem, W, H, mirrored(heights, W, H, 1, acrossX, true), tags);
        test::writeGeoTiffRgb(image, W, H, mirrored(rgb, W, H, 3, acrossX, true), tags);
        const std::string out = dir.file(std::string(name) + ".dat");
        encodeDem(dem, out, o);
        EXPECT_TRUE(test::readFile(out) == test::readFile(dir.file("north.dat")));
        nlohmann::json placed = nlohmann::json::parse(test::readFile(out + ".georef.json"));
        placed.erase("pyramid");
        EXPECT_EQ(placed, sidecar);
        const std::string images = dir.file(std::string(name) + "-rgb");
        encodeOrtho(image, images, oo);
        for (const char* file : {"/RGB.dat", "/RGB.dat.georef.json", "/dxt/RGB.dat", "/residuals/RGB.dat"}) {
            EXPECT_TRUE(test::readFile(images + file) == test::readFile(dir.file("north-rgb") + file)) << file;
        }
        // The longitude and latitude of a sample find its height (within half the quantization step).
        const auto uv = crsToRootQuad(out, west + 7.5 * step, north - 3.5 * step, true);
        EXPECT_NEAR(fileHeightAt(out, uv[0], uv[1]).height, heights[3 * W + 7], 0.5 + 1e-3);
    }
    // A +Inf sample is named by the file's own column and row.
    std::vector<float> spiked = heights;
    spiked[static_cast<size_t>(5 * W + 2)] = std::numeric_limits<float>::infinity(); // column 2, row 5 north-up
    test::GeoTiffTags tags = test::geographicTags(4326, west, north, step);
    test::setTransformation(tags, southUp);
    test::writeGeoTiff(dir.file("spiked.tif"), W, H, mirrored(spiked, W, H, 1, false, true), tags);
    try {
        encodeDem(dir.file("spiked.tif"), dir.file("spiked.dat"), o);
        ADD_FAILURE() << "an infinite height was encoded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("+Inf height at column 2, row " + std::to_string(H - 1 - 5)),
                  std::string::npos)
            << e.what();
    }
}

} // namespace
} // namespace pyramid
