// Many georeferenced files read as one (RasterSource::openMosaic): four tiles cut from one
// raster read back as that raster, sample for sample, across every seam; where files overlap
// the first listed with a value wins; gaps are nodata; files off the grid, in another CRS,
// without georeferencing or missing are refused, naming the file; tiles on both sides of the
// antimeridian join across it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

constexpr double kStep = 1.0 / 64.0; // degrees per pixel

float heightAt(int x, int y) { return static_cast<float>(x * 3 - y * 7) + 0.25f * static_cast<float>((x * y) % 5); }

// Pixels [x0, x0 + w) x [y0, y0 + h) of the whole raster (pixel (0, 0) at 10 E, 50 N) as a file.
std::string cut(test::TempDir& dir, const std::string& name, int x0, int y0, int w, int h) {
    std::vector<float> v(static_cast<size_t>(w * h));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            v[static_cast<size_t>(x + y * w)] = heightAt(x0 + x, y0 + y);
        }
    }
    const std::string path = dir.file(name);
    test::writeGeoTiff(path, w, h, v, test::geographicTags(4326, 10.0 + x0 * kStep, 50.0 - y0 * kStep, kStep));
    return path;
}

std::string errorOf(const std::vector<std::string>& paths) {
    try {
        RasterSource::openMosaic(paths, 16);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(RasterMosaic, FourTilesReadAsTheWholeRaster) {
    test::TempDir dir;
    const int W = 100, H = 70;
    const std::vector<std::string> tiles = {cut(dir, "ne.tif", 40, 0, 60, 30), cut(dir, "nw.tif", 0, 0, 40, 30),
                                            cut(dir, "sw.tif", 0, 30, 40, 40), cut(dir, "se.tif", 40, 30, 60, 40)};
    const auto mosaic = RasterSource::openMosaic(tiles, 16);
    ASSERT_EQ(mosaic->info().width, W);
    ASSERT_EQ(mosaic->info().height, H);
    ASSERT_TRUE(mosaic->info().georeference);
    EXPECT_DOUBLE_EQ(mosaic->info().georeference->pixelToCrs[0], 10.0);
    EXPECT_DOUBLE_EQ(mosaic->info().georeference->pixelToCrs[3], 50.0);
    // The whole raster, and a window across the four-tile corner.
    std::vector<float> all(static_cast<size_t>(W * H));
    mosaic->readFloat(0, 0, W, H, 0, all.data());
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) {
            ASSERT_EQ(all[static_cast<size_t>(x + y * W)], heightAt(x, y)) << x << "," << y;
        }
    }
    std::vector<float> corner(9 * 7);
    mosaic->readFloat(36, 27, 45, 34, 0, corner.data());
    for (int y = 27; y < 34; ++y) {
        for (int x = 36; x < 45; ++x) {
            EXPECT_EQ(corner[static_cast<size_t>((x - 36) + (y - 27) * 9)], heightAt(x, y)) << x << "," << y;
        }
    }
}

TEST(RasterMosaic, FirstListedWinsAndGapsAreNodata) {
    test::TempDir dir;
    const std::string a = cut(dir, "a.tif", 0, 0, 20, 10);
    // b overlaps a's east half, shifted up by 1000 so that its values are told apart.
    std::vector<float> v(20 * 10);
    for (int y = 0; y < 10; ++y) {
        for (int x = 0; x < 20; ++x) {
            v[static_cast<size_t>(x + y * 20)] = heightAt(10 + x, y) + 1000.0f;
        }
    }
    const std::string b = dir.file("b.tif");
    test::writeGeoTiff(b, 20, 10, v, test::geographicTags(4326, 10.0 + 10 * kStep, 50.0, kStep));
    // c lies below b, leaving a gap below a.
    const std::string c = cut(dir, "c.tif", 20, 10, 10, 5);
    for (const bool aFirst : {true, false}) {
        const auto m = RasterSource::openMosaic(aFirst ? std::vector<std::string>{a, b, c} : std::vector<std::string>{b, a, c}, 16);
        ASSERT_EQ(m->info().width, 30);
        ASSERT_EQ(m->info().height, 15);
        ASSERT_TRUE(m->info().nodata && std::isnan(*m->info().nodata));
        std::vector<float> all(30 * 15);
        m->readFloat(0, 0, 30, 15, 0, all.data());
        EXPECT_EQ(all[15], heightAt(15, 0) + (aFirst ? 0.0f : 1000.0f)); // in both a and b
        EXPECT_EQ(all[5], heightAt(5, 0));                                // a alone
        EXPECT_EQ(all[25], heightAt(25, 0) + 1000.0f);                    // b alone
        EXPECT_EQ(all[25 + 12 * 30], heightAt(25, 12));                   // c
        EXPECT_TRUE(std::isnan(all[5 + 12 * 30]));                        // below a: no file
    }
}

TEST(RasterMosaic, FilesThatDoNotFitAreRefusedByName) {
    test::TempDir dir;
    const std::string a = cut(dir, "a.tif", 0, 0, 20, 10);
    const std::string half = dir.file("half.tif");
    test::writeGeoTiff(half, 4, 4, std::vector<float>(16, 1.0f), test::geographicTags(4326, 10.0 + 0.5 * kStep, 50.0, kStep));
    EXPECT_NE(errorOf({a, half}).find("half.tif: lies 0.5, 0 pixels from"), std::string::npos) << errorOf({a, half});
    const std::string coarse = dir.file("coarse.tif");
    test::writeGeoTiff(coarse, 4, 4, std::vector<float>(16, 1.0f), test::geographicTags(4326, 10.0, 50.0, 2 * kStep));
    EXPECT_NE(errorOf({a, coarse}).find("coarse.tif: pixels of"), std::string::npos) << errorOf({a, coarse});
    const std::string utm = dir.file("utm.tif");
    test::writeGeoTiff(utm, 4, 4, std::vector<float>(16, 1.0f), test::projectedTags(32632, 500000, 5500000, 100));
    EXPECT_NE(errorOf({a, utm}).find("utm.tif: is in EPSG:32632"), std::string::npos) << errorOf({a, utm});
    const std::string plain = dir.file("plain.tif");
    test::writeGeoTiff(plain, 4, 4, std::vector<float>(16, 1.0f), test::GeoTiffTags{});
    EXPECT_NE(errorOf({a, plain}).find("plain.tif: has no georeferencing"), std::string::npos) << errorOf({a, plain});
    EXPECT_NE(errorOf({a, dir.file("missing.tif")}).find("missing.tif: no such file"), std::string::npos);
}

// Tiles on both sides of the antimeridian (179.5..180 E and -180..-179.875 E, one turn a whole
// 23040 pixels) join across it as the one raster 179.5..180.125 E, whichever is listed first;
// tiles that do not cross it, or go round the globe, keep the longitudes they have.
TEST(RasterMosaic, TilesOnBothSidesOfTheAntimeridianJoinAcrossIt) {
    test::TempDir dir;
    const int H = 6;
    auto part = [&](const std::string& name, int x0, int w, double west) {
        std::vector<float> v(static_cast<size_t>(w * H));
        for (int y = 0; y < H; ++y) {
            for (int x = 0; x < w; ++x) {
                v[static_cast<size_t>(x + y * w)] = heightAt(x0 + x, y);
            }
        }
        const std::string path = dir.file(name);
        test::writeGeoTiff(path, w, H, v, test::geographicTags(4326, west, 10.0, kStep));
        return path;
    };
    const std::string east = part("east.tif", 0, 32, 179.5);   // columns 0..31 of the whole
    const std::string west = part("west.tif", 32, 8, -180.0);  // columns 32..39, beyond 180
    for (const auto& files : {std::vector<std::string>{east, west}, std::vector<std::string>{west, east}}) {
        const auto mosaic = RasterSource::openMosaic(files, 16);
        ASSERT_EQ(mosaic->info().width, 40) << files[0];
        EXPECT_DOUBLE_EQ(mosaic->info().georeference->pixelToCrs[0], 179.5) << files[0];
        std::vector<float> all(static_cast<size_t>(40 * H));
        mosaic->readFloat(0, 0, 40, H, 0, all.data());
        for (int y = 0; y < H; ++y) {
            for (int x = 0; x < 40; ++x) {
                ASSERT_EQ(all[static_cast<size_t>(x + y * 40)], heightAt(x, y)) << files[0] << " " << x << "," << y;
            }
        }
    }
    // A tile labelled across it (-180.125..-179.875 E, the whole's columns 24..39) joins too.
    const std::string across = part("across.tif", 24, 16, -180.125);
    const auto joined = RasterSource::openMosaic({across, east}, 16);
    ASSERT_EQ(joined->info().width, 40);
    EXPECT_DOUBLE_EQ(joined->info().georeference->pixelToCrs[0], 179.5);
    std::vector<float> row(40);
    joined->readFloat(0, 2, 40, 3, 0, row.data());
    for (int x = 0; x < 40; ++x) {
        EXPECT_EQ(row[static_cast<size_t>(x)], heightAt(x, 2)) << x;
    }
    // Away from the antimeridian, a gap between two tiles stays where it is.
    const std::string a = part("a.tif", 0, 8, -10.0), b = part("b.tif", 0, 8, 170.0);
    const auto apart = RasterSource::openMosaic({b, a}, 16);
    EXPECT_DOUBLE_EQ(apart->info().georeference->pixelToCrs[0], -10.0);
    EXPECT_EQ(apart->info().width, 180 * 64 + 8);
}

} // namespace
} // namespace pyramid
