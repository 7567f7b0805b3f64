// Many files, one map: the preprocessors build from a mosaic of georeferenced files.
// * Seams: four tiles cut from one raster give the bytes of the pyramid built from the whole
//   raster, planar and spherical, DEM and ortho;
// * overlaps at two resolutions take the finer file; a UTM map beside a geographic one joins
//   within the resampling error; planar mosaics of several grids are resampled onto the finest,
//   whose own samples are kept as they are, as are those of files of another sample type on
//   its grid;
// * on the command line, a VRT over the tiles, a list file and a directory give the same bytes
//   as the files named one by one; a file without georeferencing and a missing one are refused
//   by name, with nothing written; --priority last lets the last listed file win overlaps.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/encode/ortho/sphere_ortho_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/map_projection.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sphere_placement.hpp"

namespace pyramid {
namespace {

std::vector<uint8_t> bytesOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A raster of 1/64-degree pixels with its first pixel's corner at (west, north).
struct Grid {
    double west, north, step;
};

float heightAt(int x, int y) {
    return 800.0f + static_cast<float>(x * 3 - y * 5) + 0.5f * static_cast<float>((x * 7 + y * 3) % 11);
}

// Pixels [x0, x0 + w) x [y0, y0 + h) of the raster whose pixel (x, y) holds heightAt(x, y).
std::string cut(const test::TempDir& dir, const std::string& name, const Grid& g, int x0, int y0, int w, int h) {
    std::vector<float> v(static_cast<size_t>(w * h));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            v[static_cast<size_t>(x + y * w)] = heightAt(x0 + x, y0 + y);
        }
    }
    const std::string path = dir.file(name);
    test::writeGeoTiff(path, w, h, v, test::geographicTags(4326, g.west + x0 * g.step, g.north - y0 * g.step, g.step));
    return path;
}

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

TEST(Mosaic, PlanarGridsAreResampledOntoTheFinest) {
    test::TempDir dir;
    const test::Slope slope(46.5, -121.5);
    // The finest: geographic, 1/256 degree over 121.6..121.4 W, 46.6..46.4 N. Beside it to the
    // east and overlapping it, UTM 10N at 1 km: its pixels are resampled onto the geographic grid.
    const int GW = 51, GH = 51;
    std::vector<float> g(static_cast<size_t>(GW * GH));
    for (int j = 0; j < GH; ++j) {
        for (int i = 0; i < GW; ++i) {
            g[static_cast<size_t>(i + j * GW)] =
                static_cast<float>(slope(46.6 - (j + 0.5) / 256.0, -121.6 + (i + 0.5) / 256.0)) + 0.001f * static_cast<float>(i % 3);
        }
    }
    const std::string geo = dir.file("geo.tif");
    test::writeGeoTiff(geo, GW, GH, g, test::geographicTags(4326, -121.6, 46.6, 1.0 / 256.0));
    const std::string utm = dir.file("utm.tif");
    test::writeGeoTiff(utm, 1, 1, {0.0f}, test::projectedTags(32610, 0, 0, 1));
    const auto projection = MapProjection::of(*RasterSource::open(utm)->info().georeference, utm);
    double ux0 = 0, uy0 = 0, ux1 = 0, uy1 = 0;
    ASSERT_TRUE(projection->forward(46.62, -121.45, ux0, uy0));
    ASSERT_TRUE(projection->forward(46.38, -121.2, ux1, uy1));
    const double step = 1000.0;
    const int UW = static_cast<int>((ux1 - ux0) / step), UH = static_cast<int>((uy0 - uy1) / step);
    std::vector<float> u(static_cast<size_t>(UW * UH));
    for (int j = 0; j < UH; ++j) {
        for (int i = 0; i < UW; ++i) {
            double lat = 0, lon = 0;
            projection->reverse(ux0 + (i + 0.5) * step, uy0 - (j + 0.5) * step, lat, lon);
            u[static_cast<size_t>(i + j * UW)] = static_cast<float>(slope(lat, lon));
        }
    }
    test::writeGeoTiff(utm, UW, UH, u, test::projectedTags(32610, ux0, uy0, step));
    // The UTM map listed first, --crs naming the geographic one: the finest file is in it, so
    // its grid is the mosaic's; listing the geographic map first gives the same mosaic.
    const auto mosaic = openPlanarMosaic({utm, geo}, 16, false, PlanarTarget{"EPSG:4326", std::nullopt});
    {
        const auto listed = openPlanarMosaic({geo, utm}, 16);
        EXPECT_EQ(listed->info().width, mosaic->info().width);
        EXPECT_EQ(listed->info().height, mosaic->info().height);
        EXPECT_EQ(listed->info().georeference->pixelToCrs, mosaic->info().georeference->pixelToCrs);
    }
    const RasterInfo& info = mosaic->info();
    ASSERT_TRUE(info.georeference);
    EXPECT_EQ(info.georeference->crsText(), "EPSG:4326 (WGS 84)");
    const auto& t = info.georeference->pixelToCrs;
    EXPECT_DOUBLE_EQ(t[1], 1.0 / 256.0);
    EXPECT_GT(info.width, GW + 40); // reaches east over the UTM map
    std::vector<float> all(static_cast<size_t>(info.width) * static_cast<size_t>(info.height));
    mosaic->readFloat(0, 0, info.width, info.height, 0, all.data());
    int own = 0, resampled = 0, holes = 0;
    for (int j = 0; j < info.height; ++j) {
        for (int i = 0; i < info.width; ++i) {
            const double lon = t[0] + (i + 0.5) * t[1], lat = t[3] + (j + 0.5) * t[5];
            const float v = all[static_cast<size_t>(i) + static_cast<size_t>(j) * static_cast<size_t>(info.width)];
            const int gi = static_cast<int>(std::lround((lon + 121.6) * 256.0 - 0.5));
            const int gj = static_cast<int>(std::lround((46.6 - lat) * 256.0 - 0.5));
            if (gi >= 0 && gi < GW && gj >= 0 && gj < GH) {
                ++own;
                ASSERT_EQ(v, g[static_cast<size_t>(gi + gj * GW)]) << i << "," << j; // as it is
            } else if (lon > -121.44 && lon < -121.22 && lat > 46.39 && lat < 46.61) {
                ++resampled;
                EXPECT_NEAR(v, slope(lat, lon), 0.5) << lat << "," << lon;
            } else if (lon < -121.47 && (lat > 46.605 || lat < 46.395)) {
                ++holes; // above and below the geographic map, west of the UTM one: no file
                EXPECT_TRUE(std::isnan(v)) << lat << "," << lon;
            }
        }
    }
    EXPECT_EQ(own, GW * GH);
    EXPECT_GT(resampled, 1000);
    EXPECT_GT(holes, 0);
    // And through the encoder: a planar pyramid of both, placed on the geographic grid.
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 4;
    o.scale = 0.25;
    o.target.crs = "EPSG:4326";
    const DemReport r = encodeDem({utm, geo}, dir.file("both.dat"), o);
    ASSERT_TRUE(r.georeference);
    EXPECT_EQ(r.georeference->crs.epsg, 4326);
    EXPECT_GT(r.levels.back().samples, 5000);
    EXPECT_LE(r.levels.back().maxError, 0.125);

    // Without --crs, the first file's CRS (UTM) takes the mosaic, at the finest file's ground
    // size (the geographic map's pixels, in metres) on whole multiples of it: everything is
    // resampled, the geographic map's pixels too.
    const auto inUtm = openPlanarMosaic({utm, geo}, 16);
    const RasterInfo& ui = inUtm->info();
    ASSERT_TRUE(ui.georeference);
    EXPECT_EQ(ui.georeference->epsg, 32610);
    const auto& ut = ui.georeference->pixelToCrs;
    // The east-west side of a 1/256-degree pixel at the geographic map's centre (46.5 N).
    const double side = 6378137.0 * (std::numbers::pi / 180.0) / 256.0 * std::cos(46.5 * std::numbers::pi / 180.0);
    EXPECT_NEAR(ut[1], side, 0.001 * side);
    EXPECT_EQ(ut[1], -ut[5]);
    EXPECT_EQ(ut[2], 0.0);
    EXPECT_LT(std::fabs(std::remainder(ut[0], ut[1])), 1e-9 * ut[1]);
    EXPECT_LT(std::fabs(std::remainder(ut[3], ut[1])), 1e-9 * ut[1]);
    std::vector<float> inside(static_cast<size_t>(ui.width) * static_cast<size_t>(ui.height));
    inUtm->readFloat(0, 0, ui.width, ui.height, 0, inside.data());
    int checked = 0;
    for (int j = 0; j < ui.height; ++j) {
        for (int i = 0; i < ui.width; ++i) {
            double lat = 0, lon = 0;
            projection->reverse(ut[0] + (i + 0.5) * ut[1], ut[3] + (j + 0.5) * ut[5], lat, lon);
            const float v = inside[static_cast<size_t>(i) + static_cast<size_t>(j) * static_cast<size_t>(ui.width)];
            if (lon > -121.59 && lon < -121.41 && lat > 46.41 && lat < 46.59) { // inside the geographic map
                ++checked;
                EXPECT_NEAR(v, slope(lat, lon), 0.05) << lat << "," << lon;
            }
        }
    }
    EXPECT_GT(checked, 500);
}

TEST(Mosaic, PlanarExtentCutsAndWidensOnTheGrid) {
    test::TempDir dir;
    const Grid g{7.0, 46.0, 1.0 / 64.0};
    const std::string whole = cut(dir, "whole.tif", g, 0, 0, 70, 50);
    // A window of the file, named by ground coordinates on its pixel edges: exactly its pixels.
    PlanarTarget window;
    window.extent = std::array<double, 4>{7.0 + 10 * g.step, 46.0 - 40 * g.step, 7.0 + 30 * g.step, 46.0 - 5 * g.step};
    const auto cutOut = openPlanarMosaic({whole}, 16, false, window);
    ASSERT_EQ(cutOut->info().width, 20);
    ASSERT_EQ(cutOut->info().height, 35);
    std::vector<float> v(20 * 35);
    cutOut->readFloat(0, 0, 20, 35, 0, v.data());
    for (int y = 0; y < 35; ++y) {
        for (int x = 0; x < 20; ++x) {
            ASSERT_EQ(v[static_cast<size_t>(x + 20 * y)], heightAt(10 + x, 5 + y)) << x << "," << y;
        }
    }
    EXPECT_DOUBLE_EQ(cutOut->info().georeference->pixelToCrs[0], 7.0 + 10 * g.step);
    // Beyond the file, widened to whole pixels: nodata (NaN) around the file's own samples.
    PlanarTarget wide;
    wide.extent = std::array<double, 4>{6.95, 45.2, 8.2, 46.1};
    const auto widened = openPlanarMosaic({whole}, 16, false, wide);
    const RasterInfo& w = widened->info();
    const int left = static_cast<int>(std::ceil(0.05 / g.step - 1e-9)), top = static_cast<int>(std::ceil(0.1 / g.step - 1e-9));
    ASSERT_EQ(w.width, left + static_cast<int>(std::ceil(1.2 / g.step - 1e-9)));
    std::vector<float> all(static_cast<size_t>(w.width) * static_cast<size_t>(w.height));
    widened->readFloat(0, 0, w.width, w.height, 0, all.data());
    for (int y = 0; y < w.height; ++y) {
        for (int x = 0; x < w.width; ++x) {
            const float got = all[static_cast<size_t>(x) + static_cast<size_t>(y) * static_cast<size_t>(w.width)];
            const int fx = x - left, fy = y - top;
            if (fx >= 0 && fx < 70 && fy >= 0 && fy < 50) {
                ASSERT_EQ(got, heightAt(fx, fy)) << x << "," << y;
            } else {
                ASSERT_TRUE(std::isnan(got)) << x << "," << y;
            }
        }
    }
    // Targets that cannot be used are refused by option.
    auto refused = [&](const PlanarTarget& t) -> std::string {
        try {
            openPlanarMosaic({whole}, 16, false, t);
        } catch (const OptionError& e) {
            return e.option() + ": " + e.problem();
        }
        return "accepted";
    };
    EXPECT_NE(refused(PlanarTarget{"WGS84", std::nullopt}).find("crs: 'WGS84' is not a CRS"), std::string::npos);
    EXPECT_NE(refused(PlanarTarget{"EPSG:1", std::nullopt}).find("crs: EPSG:1 is neither"), std::string::npos);
    EXPECT_NE(refused(PlanarTarget{"", std::array<double, 4>{0.0, 0.0, 1.0, 1.0}}).find("extent: covers none"), std::string::npos);
    EXPECT_NE(refused(PlanarTarget{"", std::array<double, 4>{8.0, 46.0, 7.0, 47.0}}).find("extent: must be"), std::string::npos);
    EXPECT_THROW(PlanarTarget::parseExtent("1,2,3"), OptionError);
    EXPECT_THROW(PlanarTarget::parseExtent("1,2,3,4x"), OptionError);
    EXPECT_EQ(PlanarTarget::parseExtent("-1,2.5,3,4e1"), (std::array<double, 4>{-1.0, 2.5, 3.0, 40.0}));
    // The same CRS named by --crs and the whole file as the extent: the file as it is.
    PlanarTarget same{"EPSG:4326", std::array<double, 4>{7.0, 46.0 - 50 * g.step, 7.0 + 70 * g.step, 46.0}};
    EXPECT_EQ(openPlanarMosaic({whole}, 16, false, same)->path(), whole);
}

TEST(Mosaic, PlanarFilesOfAnotherSampleTypeOnTheGridKeepTheirSamples) {
    test::TempDir dir;
    // One DEM of 3-arc-second pixels (a step no binary fraction holds) with nodata holes, cut in
    // two on its grid: the west part int16, the east part float32, both declaring -32768. Their
    // sample types keep them in two groups, but every pixel is still its own sample, by value: a
    // hole stays a hole and its neighbours keep their heights, whichever file is listed first.
    const int W = 60, H = 40, split = 25;
    const double step = 1.0 / 1200.0;
    const auto heightOf = [](int x, int y) { return static_cast<int16_t>(800 + 3 * x - 5 * y + (x * 7 + y * 3) % 11); };
    const auto hole = [](int x, int y) {
        return (x >= 40 && x < 43 && y >= 10 && y < 12) || (x == 30 && y == 20) || (x == 5 && y == 7);
    };
    std::vector<int16_t> whole(static_cast<size_t>(W * H)), westPart(static_cast<size_t>(split * H));
    std::vector<float> eastPart(static_cast<size_t>((W - split) * H));
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) {
            const int16_t v = hole(x, y) ? int16_t{-32768} : heightOf(x, y);
            whole[static_cast<size_t>(x + y * W)] = v;
            if (x < split) {
                westPart[static_cast<size_t>(x + y * split)] = v;
            } else {
                eastPart[static_cast<size_t>(x - split + y * (W - split))] = v;
            }
        }
    }
    const auto tags = [&](int x0) {
        test::GeoTiffTags t = test::geographicTags(4326, -121.5 + x0 * step, 46.5, step);
        t.gdalNodata = "-32768";
        return t;
    };
    const std::string wholePath = dir.file("whole.tif"), west = dir.file("west.tif"), east = dir.file("east.tif");
    test::writeGeoTiffInt16(wholePath, W, H, whole, tags(0));
    test::writeGeoTiffInt16(west, split, H, westPart, tags(0));
    test::writeGeoTiff(east, W - split, H, eastPart, tags(split));
    for (const bool westFirst : {true, false}) {
        const std::vector<std::string> inputs = westFirst ? std::vector<std::string>{west, east}
                                                          : std::vector<std::string>{east, west};
        const auto m = openPlanarMosaic(inputs, 16);
        ASSERT_EQ(m->info().width, W);
        ASSERT_EQ(m->info().height, H);
        ASSERT_TRUE(m->info().nodata);
        EXPECT_EQ(*m->info().nodata, -32768.0);
        std::vector<float> all(static_cast<size_t>(W * H));
        m->readFloat(0, 0, W, H, 0, all.data());
        for (int y = 0; y < H; ++y) {
            for (int x = 0; x < W; ++x) {
                const float expected = hole(x, y) ? -32768.0f : static_cast<float>(heightOf(x, y));
                ASSERT_EQ(all[static_cast<size_t>(x + y * W)], expected) << x << "," << y << " " << inputs[0];
            }
        }
    }
    // Through the encoder: the bytes of the pyramid built from the whole int16 raster.
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 4;
    o.scale = 0.25;
    const DemReport single = encodeDem(wholePath, dir.file("whole.dat"), o);
    const DemReport mixed = encodeDem({west, east}, dir.file("mixed.dat"), o);
    EXPECT_EQ(mixed.nodataFilled, single.nodataFilled);
    EXPECT_TRUE(bytesOf(dir.file("whole.dat")) == bytesOf(dir.file("mixed.dat")));
}

TEST(Mosaic, CommandLinesTakeListsDirectoriesAndVrts) {
    test::TempDir dir;
    std::filesystem::create_directories(dir.file("tiles"));
    const Grid g{7.0, 46.0, 1.0 / 64.0};
    const std::string whole = cut(dir, "whole.tif", g, 0, 0, 70, 50);
    cut(dir, "tiles/a.tif", g, 0, 0, 30, 50);
    cut(dir, "tiles/b.tif", g, 30, 0, 40, 50);
    {
        std::ofstream list(dir.file("list.txt"));
        list << "# the tiles\ntiles/b.tif\n\ntiles/a.tif\n";
        std::ofstream vrt(dir.file("tiles.vrt"));
        vrt << "<VRTDataset rasterXSize=\"70\" rasterYSize=\"50\">\n"
               "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n"
               "    <SimpleSource><SourceFilename relativeToVRT=\"1\">tiles/a.tif</SourceFilename>"
               "<SourceBand>1</SourceBand></SimpleSource>\n"
               "    <ComplexSource><SourceFilename relativeToVRT=\"1\">tiles/b.tif</SourceFilename>"
               "<SourceBand>1</SourceBand></ComplexSource>\n"
               "  </VRTRasterBand>\n</VRTDataset>\n";
    }
    const std::string dem = test::programPath("preprocessDem");
    const std::string common = " --tile-size 32 --root-tile-size 4 --scale 0.25 -q";
    ASSERT_EQ(test::run(dem + " " + whole + " -o " + dir.file("whole.dat") + common).exitCode, 0);
    const std::vector<std::string> ways = {
        dir.file("tiles/a.tif") + " " + dir.file("tiles/b.tif"),
        "--input-list " + dir.file("list.txt"),
        dir.file("tiles"),
        dir.file("tiles.vrt"),
        "'" + dir.file("tiles") + "/*.tif'",
    };
    const std::vector<uint8_t> expected = bytesOf(dir.file("whole.dat"));
    ASSERT_FALSE(expected.empty());
    for (size_t k = 0; k < ways.size(); ++k) {
        const std::string out = dir.file("way" + std::to_string(k) + ".dat");
        const test::RunResult r = test::run(dem + " " + ways[k] + " -o " + out + common + " --report -");
        ASSERT_EQ(r.exitCode, 0) << ways[k] << ": " << r.err;
        EXPECT_TRUE(bytesOf(out) == expected) << ways[k];
        EXPECT_NE(r.out.find("\"files\""), std::string::npos) << r.out;
    }
    // pyramid verify takes the mosaic as its source, as a VRT.
    const test::RunResult v = test::run(test::programPath("pyramid") + " verify " + dir.file("way0.dat") + " --source " +
                                        dir.file("tiles.vrt"));
    EXPECT_EQ(v.exitCode, 0) << v.out << v.err;
    // --extent on the file's grid: the tiles cut to a window; verify takes the same option, and
    // without it the window is not the source any more.
    const std::string window = " --extent 7.25,45.5,7.75,45.875";
    const test::RunResult e = test::run(dem + " " + ways[0] + " -o " + dir.file("window.dat") + common + window +
                                        " --report -");
    ASSERT_EQ(e.exitCode, 0) << e.err;
    EXPECT_NE(e.out.find("\"width\": 32"), std::string::npos) << e.out;
    EXPECT_NE(e.out.find("\"height\": 24"), std::string::npos) << e.out;
    const std::string verify = test::programPath("pyramid") + " verify " + dir.file("window.dat") + " --source " +
                               dir.file("tiles.vrt");
    EXPECT_EQ(test::run(verify + window).exitCode, 0);
    EXPECT_EQ(test::run(verify).exitCode, 1);
    // --crs into UTM: resampled, and verified against the same resampling.
    const std::string utm = " --crs EPSG:32632";
    const test::RunResult u = test::run(dem + " " + ways[0] + " -o " + dir.file("utm.dat") + common + utm + " --report -");
    ASSERT_EQ(u.exitCode, 0) << u.err;
    EXPECT_NE(u.out.find("\"epsg\": 32632"), std::string::npos) << u.out;
    EXPECT_EQ(test::run(verify.substr(0, verify.find(" verify ")) + " verify " + dir.file("utm.dat") + " --source " +
                        dir.file("tiles.vrt") + utm).exitCode, 0);
    const test::RunResult bad = test::run(dem + " " + ways[0] + " -o " + dir.file("bad.dat") + common + " --crs UTM32");
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("--crs: 'UTM32' is not a CRS"), std::string::npos) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.dat")));
    // Refusals name the file; nothing is written.
    const std::string plain = dir.file("plain.tif");
    test::writeGeoTiff(plain, 4, 4, std::vector<float>(16, 1.0f), test::GeoTiffTags{});
    const test::RunResult r1 = test::run(dem + " " + dir.file("tiles/a.tif") + " " + plain + " -o " + dir.file("x.dat") + common);
    EXPECT_EQ(r1.exitCode, 1);
    EXPECT_NE(r1.err.find("plain.tif: has no georeferencing"), std::string::npos) << r1.err;
    const test::RunResult r2 =
        test::run(dem + " " + dir.file("tiles/a.tif") + " " + dir.file("gone.tif") + " -o " + dir.file("x.dat") + common);
    EXPECT_EQ(r2.exitCode, 1);
    EXPECT_NE(r2.err.find("gone.tif"), std::string::npos) << r2.err;
    EXPECT_FALSE(test::fileExists(dir.file("x.dat")));
    const test::RunResult r3 = test::run(dem + " -o " + dir.file("x.dat") + common);
    EXPECT_EQ(r3.exitCode, 2) << r3.err;
}

TEST(Mosaic, PriorityLastLetsTheLastListedWin) {
    test::TempDir dir;
    // Two tiles overlapping by 10 columns with other heights there: which one wins shows.
    const Grid g{7.0, 46.0, 1.0 / 64.0};
    const std::string a = cut(dir, "a.tif", g, 0, 0, 40, 40);
    std::vector<float> v(40 * 40);
    for (int y = 0; y < 40; ++y) {
        for (int x = 0; x < 40; ++x) {
            v[static_cast<size_t>(x + y * 40)] = heightAt(30 + x, y) + 100.0f;
        }
    }
    const std::string b = dir.file("b.tif");
    test::writeGeoTiff(b, 40, 40, v, test::geographicTags(4326, 7.0 + 30.0 / 64.0, 46.0, 1.0 / 64.0));
    const std::string dem = test::programPath("preprocessDem");
    const std::string common = " --tile-size 32 --root-tile-size 4 --scale 0.25 -q -o ";
    ASSERT_EQ(test::run(dem + " " + a + " " + b + common + dir.file("ab.dat")).exitCode, 0);
    ASSERT_EQ(test::run(dem + " " + b + " " + a + common + dir.file("ba.dat")).exitCode, 0);
    ASSERT_EQ(test::run(dem + " " + a + " " + b + " --priority last" + common + dir.file("last.dat")).exitCode, 0);
    EXPECT_FALSE(bytesOf(dir.file("ab.dat")) == bytesOf(dir.file("ba.dat")));
    EXPECT_TRUE(bytesOf(dir.file("last.dat")) == bytesOf(dir.file("ba.dat")));
    EXPECT_EQ(test::run(dem + " " + a + " --priority middle" + common + dir.file("x.dat")).exitCode, 2);
}

} // namespace
} // namespace pyramid
