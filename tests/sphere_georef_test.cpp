// Spherical pyramids of georeferenced inputs are built where the input lies: for a GeoTIFF in
// each supported CRS whose value is a known function of the position, the rebuilt heights at the
// face's vertices equal that function at their geodetic points; the real SRTM fixture lands on
// its mountain; an unsupported CRS and a contradicting --extent are refused with nothing written.
#include <gtest/gtest.h>

#include <geotiff/geovalues.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/map_projection.hpp"
#include "libpyramid/sphere/map_sources.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"
#include "tests/support/sphere_placement.hpp"

namespace pyramid {
namespace {

using test::expectPlaced;
using test::placementOptions;
using test::Slope;

struct ProjectedCase {
    int epsg;
    double lat0, lon0; // the map's centre
    double step;       // metres per pixel
};

TEST(SphericalGeoreference, ProjectedMapsLandWhereTheyAre) {
    const ProjectedCase cases[] = {
        {32610, 46.8, -121.7, 1000},  // UTM 10N: transverse Mercator
        {32661, 89.0, 30.0, 2000},    // UPS North: polar stereographic around the pole (variant A)
        {3032, -72.0, 75.0, 1500},    // Australian Antarctic: polar stereographic, variant B
        {2154, 45.0, 4.0, 1000},      // Lambert-93: Lambert conformal conic 2SP
        {3395, 1.0, 114.0, 1000},     // World Mercator
        {3857, 40.0, -8.0, 1200},     // Web Mercator
    };
    for (const ProjectedCase& c : cases) {
        SCOPED_TRACE("EPSG:" + std::to_string(c.epsg));
        test::TempDir dir;
        const std::string path = dir.file("map.tif");
        // The CRS's projection as the library reads it, to lay out the test map.
        test::writeGeoTiff(path, 1, 1, {0.0f}, test::projectedTags(c.epsg, 0, 0, 1));
        const Georeference g = *RasterSource::open(path)->info().georeference;
        const auto projection = MapProjection::of(g, path);
        double cx = 0, cy = 0;
        ASSERT_TRUE(projection->forward(c.lat0, c.lon0, cx, cy));
        const int W = 200, H = 160;
        const double x0 = cx - W / 2 * c.step, y0 = cy + H / 2 * c.step;
        const Slope height(c.lat0, c.lon0);
        std::vector<float> v(static_cast<size_t>(W * H));
        for (int j = 0; j < H; ++j) {
            for (int i = 0; i < W; ++i) {
                double lat = 0, lon = 0;
                projection->reverse(x0 + (i + 0.5) * c.step, y0 - (j + 0.5) * c.step, lat, lon);
                v[static_cast<size_t>(i + j * W)] = static_cast<float>(height(lat, lon));
            }
        }
        test::writeGeoTiff(path, W, H, v, test::projectedTags(c.epsg, x0, y0, c.step));
        auto pixelOf = [&](const GeodeticPoint& p, double& col, double& row) {
            double x = 0, y = 0;
            if (!projection->forward(p.latitude, p.longitude, x, y)) {
                return false;
            }
            col = (x - x0) / c.step - 0.5;
            row = (y0 - y) / c.step - 0.5;
            return true;
        };
        // A pixel is 1 to 2 km: misplaced by half of one, a vertex would be 5 m off.
        expectPlaced(path, c.lat0, c.lon0, 8, pixelOf, W, H, height, 0.5);
    }
}

TEST(SphericalGeoreference, GeographicMapsLandWhereTheyAre) {
    for (const bool pixelIsPoint : {false, true}) {
        SCOPED_TRACE(pixelIsPoint ? "PixelIsPoint" : "PixelIsArea");
        test::TempDir dir;
        const std::string path = dir.file("map.tif");
        const int W = 240, H = 200;
        const double west = 30.0, north = -10.0, step = 0.01; // NAD83 (GRS80) over Africa: the datum is not WGS84
        const Slope height(-11.0, 31.2);
        std::vector<float> v(static_cast<size_t>(W * H));
        for (int j = 0; j < H; ++j) {
            for (int i = 0; i < W; ++i) {
                v[static_cast<size_t>(i + j * W)] = static_cast<float>(height(north - (j + 0.5) * step, west + (i + 0.5) * step));
            }
        }
        // PixelIsPoint: the tiepoint names the first pixel's centre, so the same samples are
        // described by a point half a pixel inside.
        test::writeGeoTiff(path, W, H, v, test::geographicTags(4269, west, north, step, pixelIsPoint));
        auto pixelOf = [&](const GeodeticPoint& p, double& col, double& row) {
            col = (p.longitude - west) / step - 0.5;
            row = (north - p.latitude) / step - 0.5;
            return true;
        };
        expectPlaced(path, -11.0, 31.2, 8, pixelOf, W, H, height, 0.5);
    }
}

// A map without georeferencing is a plate carree over its extent: when that makes its pixels
// far from square (a regional image taken for the globe), the sources say so; a global map
// twice as wide as tall, a fitting extent and a georeferenced file (whose own extent places it,
// whatever its pixels) do not.
TEST(SphericalGeoreference, PixelsFarFromSquareAreAWarning) {
    test::TempDir dir;
    const auto warnings = [&](int width, int height, const std::optional<GeoExtent>& extent, bool georeferenced) {
        const std::string path = dir.file("map-" + std::to_string(width) + "x" + std::to_string(height) + ".tif");
        const std::vector<float> v(static_cast<size_t>(width * height), 100.0f);
        if (georeferenced) {
            test::writeGeoTiff(path, width, height, v, test::geographicTags(4326, 10.0, 50.0, 0.01));
        } else {
            test::writeFloatRaster(path, width, height, v);
        }
        const MapSources m = openMapSources({path}, extent, PlanetBody::parse("wgs84"), 16, SampleRead::Float, 0, 1,
                                            [](const RasterInfo&, const std::string&) { return std::nullopt; });
        return m.warnings;
    };
    const auto globe = warnings(100, 70, std::nullopt, false);
    ASSERT_EQ(globe.size(), 1u);
    EXPECT_EQ(globe[0], dir.file("map-100x70.tif") +
                            ": 100 x 70 pixels over the whole globe are 3.6 by 2.571 degrees, not square; a global map "
                            "is twice as wide as tall (--extent WEST,SOUTH,EAST,NORTH places a part of the globe)");
    EXPECT_TRUE(warnings(200, 100, std::nullopt, false).empty());
    EXPECT_TRUE(warnings(201, 100, std::nullopt, false).empty()); // within 1 %
    EXPECT_EQ(warnings(100, 100, GeoExtent{0.0, 0.0, 20.0, 10.0}, false).size(), 1u);
    EXPECT_TRUE(warnings(100, 50, GeoExtent{0.0, 0.0, 20.0, 10.0}, false).empty());
    EXPECT_TRUE(warnings(100, 70, std::nullopt, true).empty());
}

TEST(SphericalGeoreference, GridRegisteredGlobalMapAcrossTheAntimeridian) {
    // 361 x 181 PixelIsPoint samples on whole degrees, -180 and 180 both present: wider than the
    // globe by a pixel, so placed through its transform, not wrapped.
    test::TempDir dir;
    const std::string path = dir.file("global.tif");
    const int W = 361, H = 181;
    const Slope height(0.0, 0.0);
    std::vector<float> v(static_cast<size_t>(W * H));
    for (int j = 0; j < H; ++j) {
        for (int i = 0; i < W; ++i) {
            v[static_cast<size_t>(i + j * W)] = static_cast<float>(height(90.0 - j, -180.0 + i));
        }
    }
    test::writeGeoTiff(path, W, H, v, test::geographicTags(4326, -180.5, 90.5, 1.0, true));
    auto pixelOf = [](const GeodeticPoint& p, double& col, double& row) {
        col = p.longitude + 180.0;
        row = 90.0 - p.latitude;
        return true;
    };
    // 1-degree pixels of a 64 km/degree slope: bilinear interpolation is within 20 m; half a
    // pixel off would be 500 m. Face 5 is centred on the antimeridian.
    for (const double lon : {0.0, 180.0}) {
        expectPlaced(path, 0.0, lon, 5, pixelOf, W, H, height, 20.0, 4.0);
    }
}

TEST(SphericalGeoreference, RealSrtmTileOnItsMountain) {
    const std::string path = test::sharedFixturePath("inputs/mt_rainier_90m.tif");
    if (path.empty()) {
        GTEST_SKIP() << "../shared/fixtures/inputs/mt_rainier_90m.tif is not there";
    }
    // Rebuilt heights at the vertices against the file's own pixels, bilinearly between the
    // centres of 1/1200-degree pixels, the first centred on 122 W, 47 N (the fixtures' README).
    const auto source = RasterSource::open(path);
    std::vector<float> pixels(1201 * 1201);
    source->readFloat(0, 0, 1201, 1201, 0, pixels.data());
    // Vertices next to the file's nodata (-32768, GDAL_NODATA) are filled, not sampled: skipped.
    auto pixelOf = [&](const GeodeticPoint& p, double& col, double& row) {
        col = (p.longitude + 122.0) * 1200.0;
        row = (47.0 - p.latitude) * 1200.0;
        const int i = std::clamp(static_cast<int>(col), 0, 1199), j = std::clamp(static_cast<int>(row), 0, 1199);
        for (const int k : {0, 1, 1201, 1202}) {
            if (pixels[static_cast<size_t>(i + j * 1201 + k)] == -32768.0f) {
                return false;
            }
        }
        return true;
    };
    auto height = [&](double lat, double lon) {
        double col = 0, row = 0;
        (void)pixelOf(GeodeticPoint{lat, lon}, col, row);
        const int i = static_cast<int>(col), j = static_cast<int>(row);
        const double fx = col - i, fy = row - j;
        auto at = [&](int a, int b) { return static_cast<double>(pixels[static_cast<size_t>(a + b * 1201)]); };
        const double top = at(i, j) + (at(i + 1, j) - at(i, j)) * fx;
        const double bottom = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * fx;
        return top + (bottom - top) * fy;
    };
    // Heights from the float32 interpolation of the library, quantized by scale / 2.
    expectPlaced(path, 46.5, -121.5, 9, pixelOf, 1201, 1201, height, 0.126);

    // The highest vertex is within a vertex spacing (about 5 km) of the summit, 46.853 N 121.760 W,
    // 4392 m.
    test::TempDir out;
    SphericalDemOptions o = placementOptions(9);
    o.faces = {1};
    const PlanetBody body = PlanetBody::parse(o.body);
    double best = -1e9;
    GeodeticPoint top;
    o.reconstruction = [&](int f, int l, int tx, int ty, const std::vector<float>& z) {
        for (int j = 2; l == 9 && j < 35; ++j) {
            for (int i = 2; i < 35; ++i) {
                if (z[static_cast<size_t>(i + j * 37)] > best) {
                    best = z[static_cast<size_t>(i + j * 37)];
                    top = body.geodeticOf(direction(cubePoint(FaceGrid{2048, FaceGridKind::Vertices},
                                                              FaceSample{f, tx * 32 + i - 2, ty * 32 + j - 2})));
                }
            }
        }
    };
    encodeSphericalDem(path, out.file("dem"), o);
    EXPECT_GT(best, 2500.0); // the volcano: the rest of the tile stays below 2500 m
    EXPECT_LT(body.distance(top, GeodeticPoint{46.853, -121.760}), 5000.0);
}

TEST(SphericalGeoreference, UnsupportedCrsAndContradictingExtentWriteNothing) {
    test::TempDir dir;
    const std::string laea = dir.file("laea.tif");
    test::writeGeoTiff(laea, 4, 4, std::vector<float>(16, 1.0f), test::projectedTags(3035, 4321000, 3210000, 1000));
    const std::string tile = dir.file("tile.tif");
    test::writeGeoTiff(tile, 120, 120, std::vector<float>(14400, 1.0f), test::geographicTags(4326, 86, 28, 1.0 / 120));
    const std::string utm = dir.file("utm.tif");
    test::writeGeoTiff(utm, 4, 4, std::vector<float>(16, 1.0f), test::projectedTags(32610, 500000, 5200000, 1000));
    const std::string out = dir.file("out");
    auto expectRefused = [&](const std::string& input, std::optional<GeoExtent> extent, const std::string& words,
                             const char* option) {
        SphericalDemOptions o = placementOptions(3);
        o.extent = extent;
        SphericalOrthoOptions so;
        so.extent = extent;
        for (int k = 0; k < 2; ++k) {
            try {
                if (k == 0) {
                    encodeSphericalDem(input, out, o);
                } else {
                    encodeSphericalOrtho(input, out, so);
                }
                ADD_FAILURE() << "accepted: " << words;
            } catch (const OptionError& e) {
                EXPECT_STREQ(option, e.option().c_str());
                EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
            } catch (const Error& e) {
                EXPECT_EQ(option, nullptr) << e.what();
                EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
            }
            EXPECT_FALSE(std::filesystem::exists(out)) << words;
        }
    };
    expectRefused(laea, std::nullopt,
                  "laea.tif: EPSG:3035 (ETRS89-extended / LAEA Europe) is in the Lambert azimuthal equal-area "
                  "projection, which is not supported; reproject it to EPSG:4326",
                  nullptr);
    expectRefused(tile, GeoExtent{-180, -90, 180, 90},
                  "-180,-90,180,90 contradicts the file's georeferencing (86,27,87,28 in EPSG:4326 (WGS 84)); leave "
                  "--extent out",
                  "extent");
    expectRefused(utm, GeoExtent{-123, 46, -121, 48}, "the file places itself (EPSG:32610 (WGS 84 / UTM zone 10N))",
                  "extent");

    // Within half a pixel an extent repeats the file's (grid- or cell-registered): accepted.
    SphericalDemOptions o = placementOptions(3);
    o.faces = {4};
    o.extent = GeoExtent{86.004, 26.996, 86.996, 28.004};
    const SphericalDemReport r = encodeSphericalDem(tile, out, o);
    EXPECT_EQ(r.extent.west, 86.0);
    EXPECT_EQ(r.crs, "EPSG:4326 (WGS 84)");
}

} // namespace
} // namespace pyramid
