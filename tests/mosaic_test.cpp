// Many files, one map: the preprocessors build from a mosaic of georeferenced files.
// * Seams: four tiles cut from one raster give the bytes of the pyramid built from the whole
//   raster, planar and spherical, DEM and ortho, and across the antimeridian;
// * on a planet, overlaps at two resolutions take the finer file, and a UTM map beside a
//   geographic one joins within the resampling error.
// (Planar mosaics of several grids: mosaic_planar_test.cpp; command lines: mosaic_cli_test.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/map_projection.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/mosaic_cuts.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sphere_placement.hpp"

namespace pyramid {
namespace {

using test::bytesOf;
using test::cut;
using test::Grid;

struct Cut {
    std::string whole;
    std::vector<std::string> tiles; // listed in an order other than the raster's
};

Cut cutInFour(const test::TempDir& dir, const Grid& g, int W, int H, int sx, int sy) {
    Cut c;
    c.whole = cut(dir, "whole.tif", g, 0, 0, W, H);
    c.tiles = {cut(dir, "t3.tif", g, sx, sy, W - sx, H - sy), cut(dir, "t0.tif", g, 0, 0, sx, sy),
               cut(dir, "t2.tif", g, 0, sy, sx, H - sy), cut(dir, "t1.tif", g, sx, 0, W - sx, sy)};
    return c;
}

TEST(Mosaic, PlanarTilesGiveTheWholeRastersBytes) {
    test::TempDir dir;
    const Cut c = cutInFour(dir, Grid{7.0, 46.0, 1.0 / 64.0}, 97, 65, 41, 29);
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 4;
    o.scale = 0.25;
    const DemReport whole = encodeDem(c.whole, dir.file("whole.dat"), o);
    const DemReport tiles = encodeDem(c.tiles, dir.file("tiles.dat"), o);
    EXPECT_EQ(tiles.inputs.size(), 4u);
    EXPECT_GT(whole.levels.back().samples, 1000);
    EXPECT_TRUE(bytesOf(dir.file("whole.dat")) == bytesOf(dir.file("tiles.dat")));
    EXPECT_EQ(whole.levels.back().maxError, tiles.levels.back().maxError);
}

TEST(Mosaic, SphericalTilesGiveTheWholeRastersBytes) {
    test::TempDir dir;
    const Cut c = cutInFour(dir, Grid{7.0, 46.0, 1.0 / 16.0}, 80, 64, 37, 30);
    SphericalDemOptions o = test::placementOptions(9);
    o.faces = {3};
    encodeSphericalDem(c.whole, dir.file("whole"), o);
    const SphericalDemReport tiles = encodeSphericalDem(c.tiles, dir.file("tiles"), o);
    EXPECT_EQ(tiles.crs, "EPSG:4326 (WGS 84)");
    EXPECT_GT(tiles.faces[0].dem.levels.back().samples, 1000);
    EXPECT_TRUE(bytesOf(dir.file("whole/DEM3.dat")) == bytesOf(dir.file("tiles/DEM3.dat")));

    // Imagery too: 8-bit RGB tiles of one image.
    const int W = 80, H = 64;
    const auto rgbOf = [](int x, int y) {
        return std::array<uint8_t, 3>{static_cast<uint8_t>(x * 3), static_cast<uint8_t>(y * 4), static_cast<uint8_t>(x ^ y)};
    };
    const auto rgbCut = [&](const std::string& name, int x0, int y0, int w, int h) {
        std::vector<uint8_t> v(static_cast<size_t>(w * h * 3));
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const auto p = rgbOf(x0 + x, y0 + y);
                std::copy(p.begin(), p.end(), v.begin() + (x + y * w) * 3);
            }
        }
        const std::string path = dir.file(name);
        test::writeGeoTiffRgb(path, w, h, v, test::geographicTags(4326, 7.0 + x0 / 16.0, 46.0 - y0 / 16.0, 1.0 / 16.0));
        return path;
    };
    const std::string image = rgbCut("image.tif", 0, 0, W, H);
    const std::vector<std::string> parts = {rgbCut("i1.tif", 37, 0, W - 37, H), rgbCut("i0.tif", 0, 0, 37, H)};
    SphericalOrthoOptions so;
    so.faces = {3};
    so.ortho.levels.tileSize = 64;
    so.ortho.levels.maxLevel = 5;
    encodeSphericalOrtho(image, dir.file("image"), so);
    encodeSphericalOrtho(parts, dir.file("parts"), so);
    for (const std::string file : {"RGB3.dat", "dxt/RGB3.dat", "residuals/RGB3.dat"}) {
        EXPECT_TRUE(bytesOf(dir.file("image/") + file) == bytesOf(dir.file("parts/") + file)) << file;
        EXPECT_FALSE(bytesOf(dir.file("parts/") + file).empty()) << file;
    }
}

// Tiles on both sides of the antimeridian (170..180 E, and -180..-170 E: its next 160 columns)
// give the bytes of the one raster 170..190 E, on the face that holds them and on one that
// does not (which they would otherwise reach, as a mosaic round the globe).
TEST(Mosaic, TilesAcrossTheAntimeridianGiveTheWholeRastersBytes) {
    test::TempDir dir;
    const Grid g{170.0, 10.0, 1.0 / 16.0};
    const std::string whole = cut(dir, "whole.tif", g, 0, 0, 320, 64);
    const std::vector<std::string> tiles = {cut(dir, "w.tif", Grid{g.west - 360.0, g.north, g.step}, 160, 0, 160, 64),
                                            cut(dir, "e.tif", g, 0, 0, 160, 64)};
    SphericalDemOptions o = test::placementOptions(7);
    const int held = test::faceOf(8.0, 180.0), away = test::faceOf(8.0, 0.0);
    o.faces = {held, away};
    encodeSphericalDem(whole, dir.file("whole"), o);
    encodeSphericalDem(tiles, dir.file("tiles"), o);
    const std::string heldFile = "DEM" + std::to_string(held) + ".dat", awayFile = "DEM" + std::to_string(away) + ".dat";
    for (const std::string& file : {heldFile, awayFile}) {
        EXPECT_TRUE(bytesOf(dir.file("whole/") + file) == bytesOf(dir.file("tiles/") + file)) << file;
    }
    EXPECT_LT(bytesOf(dir.file("tiles/") + awayFile).size() * 4, bytesOf(dir.file("tiles/") + heldFile).size());
}

// The heights a spherical build of `maps` rebuilds at the finest vertices of `face`, with each
// vertex's geodetic point.
struct Vertex {
    GeodeticPoint p;
    double z;
};
std::vector<Vertex> finestVertices(const std::vector<std::string>& maps, int face, int maxLevel) {
    SphericalDemOptions o = test::placementOptions(maxLevel);
    o.faces = {face};
    const PlanetBody body = PlanetBody::parse(o.body);
    const int64_t N = int64_t{4} << maxLevel;
    const int n = 32;
    std::vector<Vertex> out;
    o.reconstruction = [&](int f, int l, int tx, int ty, const std::vector<float>& z) {
        if (l != maxLevel) {
            return;
        }
        for (int j = 2; j < n + 2; ++j) {
            for (int i = 2; i < n + 2; ++i) {
                const FaceSample s{f, tx * n + i - 2, ty * n + j - 2};
                out.push_back({body.geodeticOf(direction(cubePoint(FaceGrid{N, FaceGridKind::Vertices}, s))),
                               static_cast<double>(z[static_cast<size_t>(i + j * (n + 5))])});
            }
        }
    };
    test::TempDir dir;
    encodeSphericalDem(maps, dir.file("out"), o);
    return out;
}

TEST(Mosaic, WhereResolutionsOverlapTheFinerWins) {
    test::TempDir dir;
    const test::Slope slope(45.0, 10.0);
    // A coarse map of 0.5-degree pixels over 40..50 N, 5..15 E, 1000 m above the slope; a fine
    // one of 1/32 degree over 44..46 N, 9..11 E on the slope itself. The coarse one is listed
    // first: resolution decides before order.
    const auto write = [&](const std::string& name, double west, double north, double step, int w, int h, double lift) {
        std::vector<float> v(static_cast<size_t>(w * h));
        for (int j = 0; j < h; ++j) {
            for (int i = 0; i < w; ++i) {
                v[static_cast<size_t>(i + j * w)] =
                    static_cast<float>(slope(north - (j + 0.5) * step, west + (i + 0.5) * step) + lift);
            }
        }
        const std::string path = dir.file(name);
        test::writeGeoTiff(path, w, h, v, test::geographicTags(4326, west, north, step));
        return path;
    };
    const std::string coarse = write("coarse.tif", 5.0, 50.0, 0.5, 20, 20, 1000.0);
    const std::string fine = write("fine.tif", 9.0, 46.0, 1.0 / 32.0, 64, 64, 0.0);
    int onFine = 0, onCoarse = 0;
    for (const Vertex& v : finestVertices({coarse, fine}, 3, 8)) {
        const double lat = v.p.latitude, lon = v.p.longitude;
        const double expected = slope(lat, lon);
        if (lat > 44.1 && lat < 45.9 && lon > 9.1 && lon < 10.9) {
            ++onFine;
            EXPECT_NEAR(v.z, expected, 0.5) << lat << "," << lon;
        } else if (lat > 40.6 && lat < 49.4 && lon > 5.6 && lon < 14.4 && (lat < 43.5 || lat > 46.5 || lon < 8.5 || lon > 11.5)) {
            ++onCoarse;
            EXPECT_NEAR(v.z, expected + 1000.0, 20.0) << lat << "," << lon; // 0.5-degree bilinear
        }
    }
    EXPECT_GT(onFine, 100);
    EXPECT_GT(onCoarse, 1000);
}

TEST(Mosaic, UtmBesideGeographicJoinsWithoutASeam) {
    test::TempDir dir;
    const test::Slope slope(46.5, -121.5);
    // West: geographic, 1/64 degree, 121.75..121.5 W; east: UTM 10N, 100 m pixels, from 121.5 W.
    const int GW = 16, GH = 64;
    std::vector<float> g(static_cast<size_t>(GW * GH));
    for (int j = 0; j < GH; ++j) {
        for (int i = 0; i < GW; ++i) {
            g[static_cast<size_t>(i + j * GW)] = static_cast<float>(slope(47.0 - (j + 0.5) / 64.0, -121.75 + (i + 0.5) / 64.0));
        }
    }
    const std::string west = dir.file("west.tif");
    test::writeGeoTiff(west, GW, GH, g, test::geographicTags(4326, -121.75, 47.0, 1.0 / 64.0));
    const std::string east = dir.file("east.tif");
    test::writeGeoTiff(east, 1, 1, {0.0f}, test::projectedTags(32610, 0, 0, 1));
    const auto projection = MapProjection::of(*RasterSource::open(east)->info().georeference, east);
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    ASSERT_TRUE(projection->forward(47.0, -121.5, x0, y0));
    ASSERT_TRUE(projection->forward(46.0, -121.2, x1, y1));
    const double step = 100.0;
    x0 -= 2 * step; // overlapping the geographic map by two pixels
    const int UW = static_cast<int>((x1 - x0) / step), UH = static_cast<int>((y0 - y1) / step);
    std::vector<float> u(static_cast<size_t>(UW * UH));
    for (int j = 0; j < UH; ++j) {
        for (int i = 0; i < UW; ++i) {
            double lat = 0, lon = 0;
            projection->reverse(x0 + (i + 0.5) * step, y0 - (j + 0.5) * step, lat, lon);
            u[static_cast<size_t>(i + j * UW)] = static_cast<float>(slope(lat, lon));
        }
    }
    test::writeGeoTiff(east, UW, UH, u, test::projectedTags(32610, x0, y0, step));
    int near = 0, checked = 0;
    for (const Vertex& v : finestVertices({west, east}, test::faceOf(46.5, -121.5), 9)) {
        const double lat = v.p.latitude, lon = v.p.longitude;
        if (lat < 46.1 || lat > 46.9 || lon < -121.72 || lon > -121.25) {
            continue;
        }
        ++checked;
        near += std::fabs(lon + 121.5) < 0.02;
        // 1.1 km pixels of a 10 m/km slope: bilinear within 0.1 m; the quantization 0.125 m.
        EXPECT_NEAR(v.z, slope(lat, lon), 0.5) << lat << "," << lon;
    }
    EXPECT_GT(checked, 150);
    EXPECT_GT(near, 10); // vertices at the seam itself
}

} // namespace
} // namespace pyramid
