// The less common ways a GeoTIFF places itself, each checked where the spherical DEM puts the
// map (heights of a known function of the position at the face's vertices):
// * a geographic map whose ModelTransformation is rotated;
// * geographic coordinates in grads, radians or a user-defined angular unit;
// * longitudes counted from a prime meridian other than Greenwich's (Paris), geographic and
//   projected;
// * projected CRSs given by their GeoKeys alone (transverse Mercator, polar stereographic, Lambert
//   conformal conic), placed as their EPSG equivalents are, angular parameters in the geographic
//   CRS's unit included;
// and the refusals, one line naming the file and the key, of what cannot be placed (sexagesimal
// units, a unit without its size, a projected CRS without a projection or with an unknown one).
// The planar DEM tool reports these CRSs as read.
#include <gtest/gtest.h>

#include <geotiff/geokeys.h>
#include <geotiff/geovalues.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/map_projection.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sphere_placement.hpp"

namespace pyramid {
namespace {

using test::expectPlaced;
using test::Slope;

constexpr double kParis = 2.33722917; // EPSG:8903, degrees east of Greenwich (2.5969213 grads)

// Every check below builds to level 7 (512 intervals across a face, vertices some 20 km apart)
// from maps of 4 to 7 km pixels. Error budget of a reconstructed height: the residual
// quantization (scale / 2 = 0.125 m), the float32 samples (< 0.001 m at the < 4 km heights here)
// and bilinear interpolation between pixel centres. The Slope's second derivatives in latitude
// and longitude are at most 63.71 km per radian squared, so on pixels spanning s radians (rotated
// or not, a projection's pixels alike) interpolation errs by at most
// 2 * (2 * 63.71 km * s^2) / 8 = 31.9 km * s^2: 0.04 m for 0.06-degree pixels, 0.013 m for 4 km
// ones. 0.25 m bounds the sum (the worst vertices here are 0.127 m off); a map misplaced by half
// a pixel would be off by 20 m or more (10 m per km of arc).
constexpr int kLevel = 7;
constexpr double kTolerance = 0.25;

Georeference readCrs(const std::string& path) {
    const auto source = RasterSource::open(path);
    EXPECT_TRUE(source->info().georeference.has_value()) << path;
    return source->info().georeference.value_or(Georeference{});
}

// A geographic map as the test lays it out, independently of the library: CRS x is the longitude
// east of `primeMeridian` in `unitDegrees` units, y the latitude in them, and t takes pixel
// corner coordinates to CRS units (Georeference::pixelToCrs).
struct GeographicLayout {
    std::array<double, 6> t;
    double unitDegrees = 1.0;
    double primeMeridian = 0.0;

    void geodeticOf(double col, double row, double& lat, double& lon) const {
        lon = (t[0] + t[1] * col + t[2] * row) * unitDegrees + primeMeridian;
        lat = (t[3] + t[4] * col + t[5] * row) * unitDegrees;
    }
    // Pixel-centre coordinates of a point ((0, 0): the first pixel's centre).
    bool pixelOf(const GeodeticPoint& p, double& col, double& row) const {
        double lon = p.longitude - primeMeridian;
        lon -= 360.0 * std::round(lon / 360.0);
        const double dx = lon / unitDegrees - t[0], dy = p.latitude / unitDegrees - t[3];
        const double det = t[1] * t[5] - t[2] * t[4];
        col = (t[5] * dx - t[2] * dy) / det - 0.5;
        row = (t[1] * dy - t[4] * dx) / det - 0.5;
        return true;
    }
    // The Slope sampled at every pixel's centre, row 0 first.
    std::vector<float> sample(int W, int H, const Slope& height) const {
        std::vector<float> v(static_cast<size_t>(W * H));
        for (int j = 0; j < H; ++j) {
            for (int i = 0; i < W; ++i) {
                double lat = 0, lon = 0;
                geodeticOf(i + 0.5, j + 0.5, lat, lon);
                v[static_cast<size_t>(i + j * W)] = static_cast<float>(height(lat, lon));
            }
        }
        return v;
    }
};

// North-up pixels of `step` CRS units whose grid is centred on (x, y) in CRS units.
std::array<double, 6> centredGrid(double x, double y, double step, int W, int H) {
    return {x - step * W / 2, step, 0.0, y + step * H / 2, 0.0, -step};
}

// Geographic GeoKeys: GeographicTypeGeoKey `gcs` and the keys that follow it.
test::GeoTiffTags geographicKeys(int gcs, const std::vector<std::pair<int, int>>& shortKeys = {},
                                 const std::vector<std::pair<int, double>>& doubleKeys = {}) {
    test::GeoTiffTags tags;
    tags.shortKeys = {{GTModelTypeGeoKey, ModelTypeGeographic}, {GTRasterTypeGeoKey, RasterPixelIsArea},
                      {GeographicTypeGeoKey, gcs}};
    tags.shortKeys.insert(tags.shortKeys.end(), shortKeys.begin(), shortKeys.end());
    tags.doubleKeys = doubleKeys;
    return tags;
}

// Writes the Slope about (lat0, lon0) on the layout's W x H pixels with `tags` (their transform
// set from the layout) and checks where the spherical DEM puts it.
void expectGeographicPlaced(const test::TempDir& dir, test::GeoTiffTags tags, const GeographicLayout& layout,
                            double lat0, double lon0, int W, int H) {
    const std::string path = dir.file("map.tif");
    const Slope height(lat0, lon0);
    test::setTransformation(tags, layout.t);
    test::writeGeoTiff(path, W, H, layout.sample(W, H, height), tags);
    expectPlaced(
        path, lat0, lon0, kLevel, [&](const GeodeticPoint& p, double& c, double& r) { return layout.pixelOf(p, c, r); },
        W, H, height, kTolerance);
}

TEST(SphericalGeoreferenceCases, RotatedGeographicMaps) {
    // 64 x 64 pixels of 0.05 degree (3.2 degrees a side), the columns turned from east by 30
    // degrees, and by -120 (upside down and turned): every sample lands where the
    // ModelTransformation puts its centre.
    test::TempDir dir;
    const int W = 64, H = 64;
    const double s = 0.05, lat0 = 12.0, lon0 = 25.0;
    for (const double angle : {30.0, -120.0}) {
        SCOPED_TRACE("rotated by " + std::to_string(angle));
        const double c = std::cos(angle * std::numbers::pi / 180), n = std::sin(angle * std::numbers::pi / 180);
        GeographicLayout layout{{0.0, s * c, s * n, 0.0, s * n, -s * c}};
        layout.t[0] = lon0 - 32 * (layout.t[1] + layout.t[2]); // the centre pixel corner on (lat0, lon0)
        layout.t[3] = lat0 - 32 * (layout.t[4] + layout.t[5]);
        test::GeoTiffTags tags = geographicKeys(4326);
        test::setTransformation(tags, layout.t);
        test::writeGeoTiff(dir.file("map.tif"), 1, 1, {0.0f}, tags);
        const Georeference g = readCrs(dir.file("map.tif"));
        EXPECT_FALSE(g.axisAligned());
        for (int k = 0; k < 6; ++k) {
            EXPECT_DOUBLE_EQ(g.pixelToCrs[static_cast<size_t>(k)], layout.t[static_cast<size_t>(k)]) << k;
        }
        expectGeographicPlaced(dir, geographicKeys(4326), layout, lat0, lon0, W, H);
    }
}

TEST(SphericalGeoreferenceCases, GeographicUnitsOtherThanDegrees) {
    // 100 x 80 pixels of 0.06 degree, the tiepoint and pixel scale in the file's unit.
    struct Case {
        const char* what;
        std::vector<std::pair<int, int>> shortKeys;
        std::vector<std::pair<int, double>> doubleKeys;
        double unitDegrees;
    };
    const Case cases[] = {
        {"grads (9105)", {{GeogGeodeticDatumGeoKey, Datum_WGS84}, {GeogAngularUnitsGeoKey, Angular_Grad}}, {}, 0.9},
        {"radians (9101)",
         {{GeogGeodeticDatumGeoKey, Datum_WGS84}, {GeogAngularUnitsGeoKey, Angular_Radian}},
         {},
         180.0 / std::numbers::pi},
        // User-defined: arc-minutes, by their size in radians (GeogAngularUnitSizeGeoKey).
        {"user-defined arc-minutes",
         {{GeogGeodeticDatumGeoKey, Datum_WGS84}, {GeogAngularUnitsGeoKey, KvUserDefined}},
         {{GeogAngularUnitSizeGeoKey, std::numbers::pi / 10800}},
         1.0 / 60},
    };
    test::TempDir dir;
    const int W = 100, H = 80;
    const double lat0 = -30.0, lon0 = -60.0, step = 0.06;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        const test::GeoTiffTags tags = geographicKeys(KvUserDefined, c.shortKeys, c.doubleKeys);
        GeographicLayout layout{centredGrid(lon0 / c.unitDegrees, lat0 / c.unitDegrees, step / c.unitDegrees, W, H),
                                c.unitDegrees};
        test::GeoTiffTags probe = tags;
        test::setTransformation(probe, layout.t);
        test::writeGeoTiff(dir.file("map.tif"), 1, 1, {0.0f}, probe);
        const Georeference g = readCrs(dir.file("map.tif"));
        EXPECT_TRUE(g.problem.empty()) << g.problem;
        EXPECT_NEAR(g.unitInDegrees, c.unitDegrees, 1e-12 * c.unitDegrees);
        expectGeographicPlaced(dir, tags, layout, lat0, lon0, W, H);
    }
}

TEST(SphericalGeoreferenceCases, LongitudesFromTheParisMeridian) {
    // 100 x 80 pixels of 0.04 degree around Paris, the tiepoint's longitude counted from the Paris
    // meridian (GeogPrimeMeridianGeoKey 8903, or user-defined by its longitude, or NTF (Paris),
    // EPSG:4807, in grads on the Clarke 1880 (IGN) ellipsoid).
    struct Case {
        const char* what;
        test::GeoTiffTags tags;
        double unitDegrees;
    };
    const Case cases[] = {
        {"GeogPrimeMeridianGeoKey 8903",
         geographicKeys(KvUserDefined, {{GeogGeodeticDatumGeoKey, Datum_WGS84}, {GeogPrimeMeridianGeoKey, PM_Paris}}),
         1.0},
        {"GeogPrimeMeridianLongGeoKey",
         geographicKeys(KvUserDefined,
                        {{GeogGeodeticDatumGeoKey, Datum_WGS84}, {GeogPrimeMeridianGeoKey, KvUserDefined}},
                        {{GeogPrimeMeridianLongGeoKey, kParis}}),
         1.0},
        {"GeogPrimeMeridianLongGeoKey in grads",
         geographicKeys(KvUserDefined,
                        {{GeogGeodeticDatumGeoKey, Datum_WGS84},
                         {GeogAngularUnitsGeoKey, Angular_Grad},
                         {GeogPrimeMeridianGeoKey, KvUserDefined}},
                        {{GeogPrimeMeridianLongGeoKey, 2.5969213}}),
         0.9},
        {"GeogPrimeMeridianLongGeoKey in a user-defined unit (grads by their size)",
         geographicKeys(KvUserDefined,
                        {{GeogGeodeticDatumGeoKey, Datum_WGS84},
                         {GeogAngularUnitsGeoKey, KvUserDefined},
                         {GeogPrimeMeridianGeoKey, KvUserDefined}},
                        {{GeogAngularUnitSizeGeoKey, std::numbers::pi / 200}, {GeogPrimeMeridianLongGeoKey, 2.5969213}}),
         0.9},
        {"EPSG:4807 NTF (Paris)", geographicKeys(4807), 0.9},
    };
    test::TempDir dir;
    const int W = 100, H = 80;
    const double lat0 = 48.85, lon0 = 2.35, step = 0.04;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        GeographicLayout layout{
            centredGrid((lon0 - kParis) / c.unitDegrees, lat0 / c.unitDegrees, step / c.unitDegrees, W, H),
            c.unitDegrees, kParis};
        test::GeoTiffTags probe = c.tags;
        test::setTransformation(probe, layout.t);
        test::writeGeoTiff(dir.file("map.tif"), 1, 1, {0.0f}, probe);
        EXPECT_NEAR(readCrs(dir.file("map.tif")).primeMeridian, kParis, 1e-12);
        expectGeographicPlaced(dir, c.tags, layout, lat0, lon0, W, H);
    }
    // The same numbers in EPSG:4326 lie 2.337 degrees further west: the Paris map's heights are
    // found there, east of them by the meridian's longitude.
    GeographicLayout paris{centredGrid(lon0 - kParis, lat0, step, W, H), 1.0, kParis};
    const Slope height(lat0, lon0);
    test::GeoTiffTags greenwich = geographicKeys(4326);
    test::setTransformation(greenwich, paris.t);
    test::writeGeoTiff(dir.file("greenwich.tif"), W, H, paris.sample(W, H, height), greenwich);
    GeographicLayout same = paris;
    same.primeMeridian = 0.0;
    expectPlaced(
        dir.file("greenwich.tif"), lat0, lon0 - kParis, kLevel,
        [&](const GeodeticPoint& p, double& c, double& r) { return same.pixelOf(p, c, r); }, W, H,
        [&](double lat, double lon) { return height(lat, lon + kParis); }, kTolerance);
}

// A projected CRS given one way (`tested`) placed as the same CRS given another (`reference`,
// by which the test lays the map out): the key-only CRS against its EPSG code.
struct EquivalentCase {
    const char* what;
    test::GeoTiffTags reference, tested;
    double lat0, lon0; // the map's centre
};

test::GeoTiffTags epsgProjected(int epsg) { return test::projectedTags(epsg, 0, 0, 1); }

// Both CRSs project the same points to the same metres, and the map laid out by the reference
// (96 x 80 pixels of 4 km), written with the tested keys, lands where the reference puts it.
void expectEquivalent(const EquivalentCase& c) {
    SCOPED_TRACE(c.what);
    test::TempDir dir;
    const int W = 96, H = 80;
    const double step = 4000.0;
    const std::string path = dir.file("map.tif");
    test::writeGeoTiff(path, 1, 1, {0.0f}, c.reference);
    const Georeference rg = readCrs(path);
    const auto reference = MapProjection::of(rg, path);
    test::GeoTiffTags tested = c.tested;
    tested.tiepoints = {0, 0, 0, 0, 0, 0};
    tested.pixelScale = {1, 1, 0};
    test::writeGeoTiff(path, 1, 1, {0.0f}, tested);
    const Georeference tg = readCrs(path);
    ASSERT_TRUE(tg.projected);
    ASSERT_TRUE(tg.problem.empty()) << tg.problem;
    EXPECT_EQ(tg.projection.method, rg.projection.method) << tg.projection.name;
    // The centre, and a point 50 km off, to the same millimetre.
    const auto projection = MapProjection::of(tg, path);
    for (const auto& [lat, lon] : {std::pair{c.lat0, c.lon0}, std::pair{c.lat0 - 0.45, c.lon0 + 0.5}}) {
        double rx = 0, ry = 0, x = 0, y = 0;
        ASSERT_TRUE(reference->forward(lat, lon, rx, ry));
        ASSERT_TRUE(projection->forward(lat, lon, x, y));
        EXPECT_NEAR(x, rx, 1e-3) << lat << ", " << lon;
        EXPECT_NEAR(y, ry, 1e-3) << lat << ", " << lon;
    }

    double cx = 0, cy = 0;
    ASSERT_TRUE(reference->forward(c.lat0, c.lon0, cx, cy));
    const double x0 = cx - W / 2 * step, y0 = cy + H / 2 * step;
    const Slope height(c.lat0, c.lon0);
    std::vector<float> v(static_cast<size_t>(W * H));
    for (int j = 0; j < H; ++j) {
        for (int i = 0; i < W; ++i) {
            double lat = 0, lon = 0;
            reference->reverse(x0 + (i + 0.5) * step, y0 - (j + 0.5) * step, lat, lon);
            v[static_cast<size_t>(i + j * W)] = static_cast<float>(height(lat, lon));
        }
    }
    tested.tiepoints = {0, 0, 0, x0, y0, 0};
    tested.pixelScale = {step, step, 0};
    test::writeGeoTiff(path, W, H, v, tested);
    auto pixelOf = [&](const GeodeticPoint& p, double& col, double& row) {
        double x = 0, y = 0;
        if (!reference->forward(p.latitude, p.longitude, x, y)) {
            return false;
        }
        col = (x - x0) / step - 0.5;
        row = (y0 - y) / step - 0.5;
        return true;
    };
    expectPlaced(path, c.lat0, c.lon0, kLevel, pixelOf, W, H, height, kTolerance);
}

TEST(SphericalGeoreferenceCases, TransverseMercatorByItsKeysAsUtm) {
    // The parameters by ProjCoordTransGeoKey; the projection by its EPSG code (ProjectionGeoKey);
    // the parameters in grads, the unit of a user-defined geographic CRS (GeoTIFF gives a
    // projection's angles in GeogAngularUnitsGeoKey's unit).
    test::GeoTiffTags utmByProjection = epsgProjected(KvUserDefined);
    utmByProjection.shortKeys.push_back({ProjectionGeoKey, Proj_UTM_zone_10N});
    utmByProjection.shortKeys.push_back({GeographicTypeGeoKey, GCS_WGS_84});
    test::GeoTiffTags tmGrads = test::userProjectedTags(KvUserDefined, CT_TransverseMercator,
                                                        {{ProjNatOriginLatGeoKey, 0.0},
                                                         {ProjNatOriginLongGeoKey, -123.0 / 0.9},
                                                         {ProjScaleAtNatOriginGeoKey, 0.9996},
                                                         {ProjFalseEastingGeoKey, 500000.0},
                                                         {ProjFalseNorthingGeoKey, 0.0}});
    tmGrads.shortKeys.push_back({GeogGeodeticDatumGeoKey, Datum_WGS84});
    tmGrads.shortKeys.push_back({GeogAngularUnitsGeoKey, Angular_Grad});
    expectEquivalent({"ProjCoordTransGeoKey", epsgProjected(32610),
                      test::userProjectedTags(GCS_WGS_84, CT_TransverseMercator,
                                              {{ProjNatOriginLatGeoKey, 0.0},
                                               {ProjNatOriginLongGeoKey, -123.0},
                                               {ProjScaleAtNatOriginGeoKey, 0.9996},
                                               {ProjFalseEastingGeoKey, 500000.0},
                                               {ProjFalseNorthingGeoKey, 0.0}}),
                      46.8, -121.7});
    expectEquivalent({"ProjectionGeoKey 16010", epsgProjected(32610), utmByProjection, 46.8, -121.7});
    expectEquivalent({"ProjCoordTransGeoKey, angles in grads", epsgProjected(32610), tmGrads, 46.8, -121.7});

    // Grads by their size (a user-defined unit): the central meridian read in degrees.
    test::GeoTiffTags tmUserUnit = tmGrads;
    tmUserUnit.shortKeys.back() = {GeogAngularUnitsGeoKey, KvUserDefined};
    tmUserUnit.doubleKeys.push_back({GeogAngularUnitSizeGeoKey, std::numbers::pi / 200});
    tmUserUnit.tiepoints = {0, 0, 0, 500000, 5200000, 0};
    tmUserUnit.pixelScale = {1000, 1000, 0};
    test::TempDir dir;
    test::writeGeoTiff(dir.file("map.tif"), 1, 1, {0.0f}, tmUserUnit);
    const Georeference g = readCrs(dir.file("map.tif"));
    EXPECT_TRUE(g.problem.empty()) << g.problem;
    EXPECT_EQ(g.projection.method, ProjectionMethod::TransverseMercator);
    EXPECT_NEAR(g.projection.originLongitude, -123.0, 1e-12);
    EXPECT_NEAR(g.projection.originLatitude, 0.0, 1e-12);
    EXPECT_EQ(g.projection.falseEasting, 500000.0); // lengths are not angles
    EXPECT_EQ(g.projection.scale, 0.9996);
}

TEST(SphericalGeoreferenceCases, PolarStereographicAndConicByTheirKeys) {
    expectEquivalent({"polar stereographic (variant A) as EPSG:32661", epsgProjected(32661),
                      test::userProjectedTags(GCS_WGS_84, CT_PolarStereographic,
                                              {{ProjNatOriginLatGeoKey, 90.0},
                                               {ProjStraightVertPoleLongGeoKey, 0.0},
                                               {ProjScaleAtNatOriginGeoKey, 0.994},
                                               {ProjFalseEastingGeoKey, 2000000.0},
                                               {ProjFalseNorthingGeoKey, 2000000.0}}),
                      88.0, -40.0});
    expectEquivalent({"Lambert conformal conic 2SP as EPSG:2154 (Lambert-93)", epsgProjected(2154),
                      test::userProjectedTags(4171, CT_LambertConfConic_2SP,
                                              {{ProjStdParallel1GeoKey, 49.0},
                                               {ProjStdParallel2GeoKey, 44.0},
                                               {ProjFalseOriginLatGeoKey, 46.5},
                                               {ProjFalseOriginLongGeoKey, 3.0},
                                               {ProjFalseOriginEastingGeoKey, 700000.0},
                                               {ProjFalseOriginNorthingGeoKey, 6600000.0}}),
                      45.0, 4.0});
}

TEST(SphericalGeoreferenceCases, ProjectedFromTheParisMeridian) {
    // NTF (Paris) / Lambert zone II (EPSG:27572): its central meridian is Paris's, 0 east of it.
    // The same cone on a Greenwich-based CRS of the same ellipsoid (Clarke 1880 (IGN),
    // EPSG:7011) has it at 2.33722917 degrees east; misread from Greenwich, the map would lie
    // 170 km west.
    test::GeoTiffTags lambertIIGreenwich =
        test::userProjectedTags(KvUserDefined, CT_LambertConfConic_1SP,
                                {{ProjNatOriginLatGeoKey, 46.8},
                                 {ProjNatOriginLongGeoKey, kParis},
                                 {ProjScaleAtNatOriginGeoKey, 0.99987742},
                                 {ProjFalseEastingGeoKey, 600000.0},
                                 {ProjFalseNorthingGeoKey, 2200000.0}});
    lambertIIGreenwich.shortKeys.push_back({GeogGeodeticDatumGeoKey, KvUserDefined});
    lambertIIGreenwich.shortKeys.push_back({GeogEllipsoidGeoKey, Ellipse_Clarke_1880_IGN});
    expectEquivalent({"EPSG:27572 as its cone from Greenwich", lambertIIGreenwich, epsgProjected(27572), 48.85, 2.35});
}

TEST(SphericalGeoreferenceCases, WhatNoAffineTransformPlacesIsRefused) {
    struct Case {
        const char* what;
        test::GeoTiffTags tags;
        std::string message; // after "PATH: "
    };
    test::GeoTiffTags noProjection = epsgProjected(KvUserDefined);
    noProjection.shortKeys.push_back({GeographicTypeGeoKey, GCS_WGS_84});
    const Case cases[] = {
        {"sexagesimal DMS",
         geographicKeys(KvUserDefined, {{GeogGeodeticDatumGeoKey, Datum_WGS84}, {GeogAngularUnitsGeoKey, 9110}}),
         "has GeogAngularUnitsGeoKey 9110, a sexagesimal notation, not a unit of angle: no affine transform maps "
         "pixels to it"},
        {"user-defined unit without its size",
         geographicKeys(KvUserDefined,
                        {{GeogGeodeticDatumGeoKey, Datum_WGS84}, {GeogAngularUnitsGeoKey, KvUserDefined}}),
         "has a user-defined GeogAngularUnitsGeoKey (32767) without GeogAngularUnitSizeGeoKey"},
        {"projected without a projection", noProjection,
         "a user-defined projected CRS names no projection method: neither ProjectionGeoKey nor ProjCoordTransGeoKey "
         "is given"},
        {"unknown ProjCoordTransGeoKey", test::userProjectedTags(GCS_WGS_84, 99, {}),
         "a user-defined projected CRS is in the unknown (ProjCoordTransGeoKey 99) projection, which is not supported"},
        {"unsupported method by its keys",
         test::userProjectedTags(GCS_WGS_84, CT_LambertAzimEqualArea,
                                 {{ProjCenterLatGeoKey, 52.0}, {ProjCenterLongGeoKey, 10.0}}),
         "a user-defined projected CRS is in the Lambert azimuthal equal-area projection, which is not supported; "
         "reproject it to EPSG:4326"},
    };
    test::TempDir dir;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        const std::string path = dir.file("map.tif"), out = dir.file("out");
        std::filesystem::remove_all(out);
        test::GeoTiffTags tags = c.tags;
        test::setTransformation(tags, {10.0, 0.01, 0.0, 50.0, 0.0, -0.01});
        test::writeGeoTiff(path, 8, 8, std::vector<float>(64, 1.0f), tags);
        SphericalDemOptions o = test::placementOptions(3);
        try {
            encodeSphericalDem(path, out, o);
            ADD_FAILURE() << "accepted";
        } catch (const OptionError& e) {
            ADD_FAILURE() << "an option error: " << e.what();
        } catch (const Error& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
            EXPECT_EQ(m.rfind(path + ": " + c.message, 0), 0u) << m;
        }
        EXPECT_FALSE(std::filesystem::exists(out));
    }
}

TEST(SphericalGeoreferenceCases, PlanarDemReportsTheCrsAsRead) {
    // NTF (Paris) in grads, and a transverse Mercator by its keys: the report and the sidecar
    // give the unit, the meridian and the projection the spherical tools place them by; a CRS
    // they refuse gets no georeference (the pyramid is built on its pixels alone).
    test::TempDir dir;
    const std::vector<float> heights(33 * 33, 5.0f);
    test::GeoTiffTags ntf = geographicKeys(4807);
    test::setTransformation(ntf, centredGrid(0.1, 54.3, 0.01, 33, 33));
    test::writeGeoTiff(dir.file("ntf.tif"), 33, 33, heights, ntf);
    test::GeoTiffTags tm = test::userProjectedTags(GCS_WGS_84, CT_TransverseMercator,
                                                   {{ProjNatOriginLongGeoKey, -123.0},
                                                    {ProjScaleAtNatOriginGeoKey, 0.9996},
                                                    {ProjFalseEastingGeoKey, 500000.0}});
    tm.asciiKeys = {{PCSCitationGeoKey, "UTM 10N by hand"}};
    test::setTransformation(tm, centredGrid(590000, 5190000, 30, 33, 33));
    test::writeGeoTiff(dir.file("tm.tif"), 33, 33, heights, tm);
    test::GeoTiffTags dms =
        geographicKeys(KvUserDefined, {{GeogGeodeticDatumGeoKey, Datum_WGS84}, {GeogAngularUnitsGeoKey, 9110}});
    test::setTransformation(dms, centredGrid(10, 50, 0.01, 33, 33));
    test::writeGeoTiff(dir.file("dms.tif"), 33, 33, heights, dms);

    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 8;
    o.maxLevel = 2;
    const nlohmann::json n = toJson(encodeDem(dir.file("ntf.tif"), dir.file("ntf.dat"), o))["georeference"]["crs"];
    EXPECT_EQ(n["epsg"], 4807);
    EXPECT_EQ(n["name"], "NTF (Paris)");
    EXPECT_EQ(n["kind"], "geographic");
    EXPECT_NEAR(n["unit_degrees"].get<double>(), 0.9, 1e-15);
    EXPECT_NEAR(n["prime_meridian_degrees"].get<double>(), kParis, 1e-12);
    EXPECT_NEAR(n["semi_major_axis_metres"].get<double>(), 6378249.2, 1e-6);
    const nlohmann::json t = toJson(encodeDem(dir.file("tm.tif"), dir.file("tm.dat"), o))["georeference"]["crs"];
    EXPECT_TRUE(t["epsg"].is_null());
    EXPECT_EQ(t["name"], "UTM 10N by hand");
    EXPECT_EQ(t["kind"], "projected");
    EXPECT_EQ(t["projection"], "transverse Mercator");
    EXPECT_EQ(t["unit_metres"], 1.0);
    const DemReport refused = encodeDem(dir.file("dms.tif"), dir.file("dms.dat"), o);
    EXPECT_FALSE(refused.georeference.has_value());
    EXPECT_FALSE(std::filesystem::exists(dir.file("dms.dat.georef.json")));
    EXPECT_EQ(test::readFile(dir.file("dms.dat")), test::readFile(dir.file("ntf.dat"))); // the same pixels
}

} // namespace
} // namespace pyramid
