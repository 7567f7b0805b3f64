// GeoTIFF georeferencing read with libgeotiff (input/georeference.hpp) and the projections the
// spherical tools apply to it (sphere/map_projection.hpp): CRS, ellipsoid, units, raster type and
// transforms of files the tests write, the real SRTM fixture, and every supported projection
// method against the worked examples of IOGP's Guidance Note 7-2 (EPSG).
#include <gtest/gtest.h>

#include <geotiff/geokeys.h>
#include <geotiff/geovalues.h>

#include <cmath>

#include "formats/error.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/map_projection.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

Georeference readBack(const test::TempDir& dir, const test::GeoTiffTags& tags, int W = 4, int H = 3) {
    const std::string path = dir.file("g.tif");
    test::writeGeoTiff(path, W, H, std::vector<float>(static_cast<size_t>(W * H), 1.0f), tags);
    const auto source = RasterSource::open(path);
    EXPECT_TRUE(source->info().georeference.has_value());
    return source->info().georeference.value_or(Georeference{});
}

TEST(Georeference, GeographicTiepointAndScale) {
    test::TempDir dir;
    const Georeference g = readBack(dir, test::geographicTags(4326, 86.0, 28.0, 0.25));
    EXPECT_FALSE(g.projected);
    EXPECT_EQ(g.epsg, 4326);
    EXPECT_EQ(g.name, "WGS 84");
    EXPECT_EQ(g.crsText(), "EPSG:4326 (WGS 84)");
    EXPECT_DOUBLE_EQ(g.semiMajorAxis, 6378137.0);
    EXPECT_NEAR(1.0 / g.flattening, 298.257223563, 1e-6);
    EXPECT_TRUE(g.problem.empty()) << g.problem;
    EXPECT_FALSE(g.pixelIsPoint);
    const std::array<double, 6> expected{86.0, 0.25, 0.0, 28.0, 0.0, -0.25};
    EXPECT_EQ(g.pixelToCrs, expected);
}

TEST(Georeference, ReadForTiffsOfTheImageIoModuleToo) {
    test::TempDir dir;
    const std::string path = dir.file("half.tif");
    test::writeGeoTiffHalf(path, 4, 3, std::vector<uint16_t>(12, 0x3c00), test::projectedTags(32610, 500000, 5200000, 30));
    const auto source = RasterSource::open(path);
    EXPECT_EQ(source->info().type, SampleType::Float16); // described by OpenImageIO, not libtiff
    ASSERT_TRUE(source->info().georeference.has_value());
    EXPECT_EQ(source->info().georeference->epsg, 32610);
    EXPECT_EQ(source->info().georeference->pixelToCrs[0], 500000.0);
}

TEST(Georeference, PixelIsPointShiftsHalfAPixel) {
    test::TempDir dir;
    // The tiepoint names the first pixel's centre, at (86.125, 27.875): its corner is at (86, 28).
    const Georeference g = readBack(dir, test::geographicTags(4326, 86.0, 28.0, 0.25, true));
    EXPECT_TRUE(g.pixelIsPoint);
    EXPECT_DOUBLE_EQ(g.pixelToCrs[0], 86.0);
    EXPECT_DOUBLE_EQ(g.pixelToCrs[3], 28.0);
}

TEST(Georeference, ModelTransformationAndOtherEllipsoids) {
    test::TempDir dir;
    test::GeoTiffTags tags = test::geographicTags(4267, 0, 0, 1); // NAD27: Clarke 1866
    tags.tiepoints.clear();
    tags.pixelScale.clear();
    tags.transformation = {0.5, 0.1, 0, 10, 0.2, -0.5, 0, 50, 0, 0, 0, 0, 0, 0, 0, 1};
    const Georeference g = readBack(dir, tags);
    const std::array<double, 6> expected{10, 0.5, 0.1, 50, 0.2, -0.5};
    EXPECT_EQ(g.pixelToCrs, expected);
    EXPECT_FALSE(g.axisAligned());
    EXPECT_DOUBLE_EQ(g.semiMajorAxis, 6378206.4);
    EXPECT_NEAR(g.semiMajorAxis * (1 - g.flattening), 6356583.8, 1e-3);
}

TEST(Georeference, UserDefinedBodyFromItsKeys) {
    test::TempDir dir;
    test::GeoTiffTags tags = test::geographicTags(KvUserDefined, -10, 10, 1);
    tags.shortKeys.push_back({GeogGeodeticDatumGeoKey, KvUserDefined});
    tags.shortKeys.push_back({GeogEllipsoidGeoKey, KvUserDefined});
    tags.doubleKeys = {{GeogSemiMajorAxisGeoKey, 3396190.0}, {GeogSemiMinorAxisGeoKey, 3376200.0}};
    tags.asciiKeys = {{GeogCitationGeoKey, "Mars 2000"}};
    const Georeference g = readBack(dir, tags);
    EXPECT_EQ(g.epsg, 0);
    EXPECT_EQ(g.crsText(), "Mars 2000");
    EXPECT_DOUBLE_EQ(g.semiMajorAxis, 3396190.0);
    EXPECT_NEAR(g.flattening, (3396190.0 - 3376200.0) / 3396190.0, 1e-12);
}

TEST(Georeference, UnusableOnesSayWhy) {
    test::TempDir dir;
    test::GeoTiffTags gcps = test::geographicTags(4326, 0, 0, 1);
    gcps.pixelScale.clear();
    gcps.tiepoints = {0, 0, 0, 10, 20, 0, 3, 0, 0, 11, 20, 0, 0, 2, 0, 10, 19, 0};
    EXPECT_NE(readBack(dir, gcps).problem.find("ground control points"), std::string::npos);
    test::GeoTiffTags geocentric = test::geographicTags(4326, 0, 0, 1);
    geocentric.shortKeys[0] = {GTModelTypeGeoKey, ModelTypeGeocentric};
    EXPECT_NE(readBack(dir, geocentric).problem.find("geocentric"), std::string::npos);
    // No GeoKeys at all: no georeferencing (the tools place it by --extent as before).
    const std::string plain = dir.file("plain.tif");
    test::writeFloatRaster(plain, 4, 3, std::vector<float>(12, 1.0f));
    EXPECT_FALSE(RasterSource::open(plain)->info().georeference.has_value());
}

TEST(Georeference, RealSrtmTile) {
    const std::string path = test::sharedFixturePath("inputs/mt_rainier_90m.tif");
    if (path.empty()) {
        GTEST_SKIP() << "../shared/fixtures/inputs/mt_rainier_90m.tif is not there";
    }
    const auto source = RasterSource::open(path);
    const RasterInfo& info = source->info();
    ASSERT_TRUE(info.georeference.has_value());
    const Georeference& g = *info.georeference;
    EXPECT_EQ(g.epsg, 4326);
    EXPECT_FALSE(g.pixelIsPoint);
    EXPECT_TRUE(g.axisAligned());
    // 1/1200 degree pixels, the first centred on 122 W, 47 N (README of the fixtures).
    EXPECT_NEAR(g.pixelToCrs[1], 1.0 / 1200, 1e-12);
    EXPECT_NEAR(g.pixelToCrs[5], -1.0 / 1200, 1e-12);
    EXPECT_NEAR(g.pixelToCrs[0] + 0.5 * g.pixelToCrs[1], -122.0, 1e-9);
    EXPECT_NEAR(g.pixelToCrs[3] + 0.5 * g.pixelToCrs[5], 47.0, 1e-9);
    EXPECT_EQ(info.nodata, -32768.0); // GDAL_NODATA as before
}

// IOGP Guidance Note 7-2 (EPSG), the worked example of each method: the CRS by its EPSG code as
// a file names it, one point, its easting and northing in the CRS's units.
struct Example {
    int epsg;
    ProjectionMethod method;
    double latitude, longitude, easting, northing;
};

double dms(double d, double m, double s) { return (d < 0 ? -1 : 1) * (std::fabs(d) + m / 60 + s / 3600); }

TEST(MapProjection, GuidanceNoteExamples) {
    const Example examples[] = {
        {27700, ProjectionMethod::TransverseMercator, 50.5, 0.5, 577274.99, 69740.50},          // British National Grid
        {32661, ProjectionMethod::PolarStereographic, 73, 44, 3320416.75, 632668.43},           // UPS North (variant A)
        {3032, ProjectionMethod::PolarStereographic, -75, 120, 7255380.79, 7053389.56},         // variant B
        {32040, ProjectionMethod::LambertConformalConic, 28.5, -96, 2963503.91, 254759.80},     // 2SP, US survey feet
        {24200, ProjectionMethod::LambertConformalConic, dms(17, 55, 55.80), dms(-76, 56, 37.26), 255966.58,
         142493.51},                                                                             // 1SP
        {3002, ProjectionMethod::Mercator, -3, 120, 5009726.58, 569150.82},                     // variant A
        {3388, ProjectionMethod::Mercator, 53, 53, 165704.29, 5171848.07},                      // variant B
        {3857, ProjectionMethod::WebMercator, dms(24, 22, 54.433), -100.0 - 20.0 / 60, -11169055.58, 2800000.00},
    };
    test::TempDir dir;
    for (const Example& e : examples) {
        SCOPED_TRACE("EPSG:" + std::to_string(e.epsg));
        const Georeference g = readBack(dir, test::projectedTags(e.epsg, 0, 0, 1));
        ASSERT_TRUE(g.projected);
        EXPECT_EQ(g.epsg, e.epsg);
        EXPECT_EQ(g.projection.method, e.method) << g.projection.name;
        const auto projection = MapProjection::of(g, "g.tif");
        double x = 0, y = 0;
        ASSERT_TRUE(projection->forward(e.latitude, e.longitude, x, y));
        EXPECT_NEAR(x / g.unitInMetres, e.easting, 0.01);
        EXPECT_NEAR(y / g.unitInMetres, e.northing, 0.01);
        double lat = 0, lon = 0;
        projection->reverse(x, y, lat, lon);
        EXPECT_NEAR(lat, e.latitude, 1e-9);
        EXPECT_NEAR(lon, e.longitude, 1e-9);
    }
}

TEST(MapProjection, OthersAreRefusedByName) {
    test::TempDir dir;
    const Georeference g = readBack(dir, test::projectedTags(3035, 0, 0, 1));
    EXPECT_EQ(g.projection.method, ProjectionMethod::Other);
    try {
        (void)MapProjection::of(g, "laea.tif");
        ADD_FAILURE() << "EPSG:3035 accepted";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("laea.tif: EPSG:3035"), std::string::npos) << m;
        EXPECT_NE(m.find("Lambert azimuthal equal-area projection, which is not supported; reproject it to EPSG:4326"),
                  std::string::npos)
            << m;
    }
}

} // namespace
} // namespace pyramid
