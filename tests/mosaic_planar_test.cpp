// Planar mosaics of several grids (sphere/planar_mosaic.hpp): resampled onto the finest, whose own
// samples are kept as they are, as are those of files of another sample type on its grid; a
// target CRS and extent cut and widen the mosaic on the grid, and targets that cannot be used are
// refused by option.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/map_projection.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/mosaic_cuts.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sphere_placement.hpp"

namespace pyramid {
namespace {

using test::bytesOf;
using test::cut;
using test::Grid;
using test::heightAt;

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

} // namespace
} // namespace pyramid
