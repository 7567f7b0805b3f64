// SRTM height files (.hgt) read directly: big-endian int16 samples, placed by their name on the
// WGS 84 degree grid (PixelIsPoint, the edges on the cell's degree lines), -32768 as nodata.
// The same heights as a GeoTIFF of that placement give the same samples and the same pyramid
// byte for byte (the real Mount Rainier tile too); names that place nothing and sizes that are
// no square are refused naming the file; neighbouring files make a mosaic on one grid.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;

void writeHgt(const std::string& path, const std::vector<int16_t>& heights) {
    std::string bytes;
    for (const int16_t h : heights) {
        const auto u = static_cast<uint16_t>(h);
        bytes.push_back(static_cast<char>(u >> 8));
        bytes.push_back(static_cast<char>(u & 0xFF));
    }
    std::ofstream(path, std::ios::binary) << bytes;
}

// n x n heights with a ridge and a few voids.
std::vector<int16_t> heightsOf(int n) {
    std::vector<int16_t> h(static_cast<size_t>(n) * static_cast<size_t>(n));
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            h[static_cast<size_t>(y * n + x)] = static_cast<int16_t>(1200 + 15 * x - 9 * y + ((x * 7 + y * 3) % 13));
        }
    }
    h[static_cast<size_t>(n + 3)] = h[static_cast<size_t>(5 * n + 7)] = -32768;
    return h;
}

std::vector<float> samplesOf(const RasterSource& s) {
    const RasterInfo& info = s.info();
    std::vector<float> v(static_cast<size_t>(info.width) * static_cast<size_t>(info.height));
    s.readFloat(0, 0, info.width, info.height, 0, v.data());
    return v;
}

std::string bytesOf(const std::string& path) { return test::readFile(path); }

TEST(HgtInput, ReadsAsTheGeoTiffOfItsPlacement) {
    test::TempDir dir;
    const int n = 121; // one sample every 30 arc-seconds
    const std::vector<int16_t> heights = heightsOf(n);
    writeHgt(dir.file("N46W122.hgt"), heights);
    const double step = 1.0 / (n - 1);
    // Pixel (0, 0)'s corner half a step beyond the cell's north-west corner, its centre on it.
    auto tags = test::geographicTags(4326, -122.0 - step / 2, 47.0 + step / 2, step, true);
    tags.gdalNodata = "-32768";
    test::writeGeoTiffInt16(dir.file("same.tif"), n, n, heights, tags);

    const auto hgt = RasterSource::open(dir.file("N46W122.hgt"));
    const auto tif = RasterSource::open(dir.file("same.tif"));
    const RasterInfo& a = hgt->info();
    const RasterInfo& b = tif->info();
    EXPECT_EQ(a.width, n);
    EXPECT_EQ(a.height, n);
    EXPECT_EQ(a.channels, 1);
    EXPECT_EQ(a.type, SampleType::Int16);
    EXPECT_EQ(a.formatName, "hgt");
    ASSERT_TRUE(a.nodata.has_value());
    EXPECT_EQ(*a.nodata, -32768.0);
    ASSERT_TRUE(a.georeference && b.georeference);
    EXPECT_FALSE(a.georeference->projected);
    EXPECT_EQ(a.georeference->epsg, 4326);
    EXPECT_TRUE(a.georeference->pixelIsPoint);
    EXPECT_DOUBLE_EQ(a.georeference->semiMajorAxis, b.georeference->semiMajorAxis);
    EXPECT_NEAR(a.georeference->flattening, b.georeference->flattening, 1e-15);
    for (size_t k = 0; k < 6; ++k) {
        EXPECT_NEAR(a.georeference->pixelToCrs[k], b.georeference->pixelToCrs[k], 1e-12) << k;
    }
    // The centre of sample (0, 0) is the cell's north-west corner; the last, its south-east one.
    const auto& t = a.georeference->pixelToCrs;
    EXPECT_NEAR(t[0] + 0.5 * t[1], -122.0, 1e-12);
    EXPECT_NEAR(t[3] + 0.5 * t[5], 47.0, 1e-12);
    EXPECT_NEAR(t[0] + (n - 0.5) * t[1], -121.0, 1e-12);
    EXPECT_NEAR(t[3] + (n - 0.5) * t[5], 46.0, 1e-12);
    const std::vector<float> va = samplesOf(*hgt);
    EXPECT_EQ(va, samplesOf(*tif));
    EXPECT_EQ(va[static_cast<size_t>(n + 3)], -32768.0f);
    EXPECT_EQ(va[1], 1200.0f + 15.0f + 7.0f);
    // A window away from the corner.
    std::vector<float> w(3 * 2);
    hgt->readFloat(10, 20, 13, 22, 0, w.data());
    EXPECT_EQ(w[4], va[static_cast<size_t>(21 * n + 11)]);

    // The pyramid of either file is the same, and so is its placement.
    DemEncodeOptions o;
    o.threads = 2;
    encodeDem(dir.file("N46W122.hgt"), dir.file("hgt.dat"), o);
    encodeDem(dir.file("same.tif"), dir.file("tif.dat"), o);
    EXPECT_EQ(bytesOf(dir.file("hgt.dat")), bytesOf(dir.file("tif.dat")));
    EXPECT_TRUE(fs::exists(dir.file("hgt.dat.georef.json")));
}

TEST(HgtInput, TheRealMountRainierTileGivesTheGeoTiffsPyramid) {
    const std::string path = test::sharedFixturePath("inputs/mt_rainier_90m.tif");
    if (path.empty()) {
        GTEST_SKIP() << "../shared/fixtures/inputs/mt_rainier_90m.tif is not there";
    }
    test::TempDir dir;
    const auto tif = RasterSource::open(path);
    ASSERT_EQ(tif->info().width, 1201);
    std::vector<int16_t> heights;
    for (const float v : samplesOf(*tif)) {
        heights.push_back(static_cast<int16_t>(v));
    }
    writeHgt(dir.file("N46W122.hgt"), heights);
    DemEncodeOptions o;
    o.threads = 2;
    encodeDem(dir.file("N46W122.hgt"), dir.file("hgt.dat"), o);
    encodeDem(path, dir.file("tif.dat"), o);
    EXPECT_EQ(bytesOf(dir.file("hgt.dat")), bytesOf(dir.file("tif.dat")));
}

TEST(HgtInput, NamesAndSizesThatPlaceNothingAreRefused) {
    test::TempDir dir;
    const std::vector<int16_t> heights = heightsOf(11);
    const auto placed = [&](const std::string& name) {
        writeHgt(dir.file(name), heights);
        return RasterSource::open(dir.file(name))->info().georeference->pixelToCrs;
    };
    // Any case, a suffix after a dot; south and east count negative and positive.
    EXPECT_NEAR(placed("n46w122.HGT")[0] + 0.05, -122.0, 1e-12);
    EXPECT_NEAR(placed("S01E010.SRTMGL1.hgt")[0] + 0.05, 10.0, 1e-12);
    EXPECT_NEAR(placed("S01E010.SRTMGL1.hgt")[3] - 0.05, 0.0, 1e-12);
    EXPECT_NEAR(placed("S90W180.hgt")[3] - 0.05, -89.0, 1e-12);
    const auto refused = [&](const std::string& name, size_t samples, const std::string& expected) {
        std::vector<int16_t> h(samples, 5);
        writeHgt(dir.file(name), h);
        try {
            RasterSource::open(dir.file(name));
            ADD_FAILURE() << name << " was read";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind(dir.file(name) + ": " + expected, 0), 0u) << e.what();
        }
    };
    const std::string naming = "an SRTM height file's name must begin with its south-west corner";
    refused("dem.hgt", 121, naming);
    refused("N46W122x.hgt", 121, naming);
    refused("N90E000.hgt", 121, naming);
    refused("N00E180.hgt", 121, naming);
    refused("X46W122.hgt", 121, naming);
    refused("N46W122.hgt", 120, "an SRTM height file holds a square of 16-bit heights");
    refused("N47W122.hgt", 1, "an SRTM height file holds a square of 16-bit heights");
}

TEST(HgtInput, NeighbouringFilesMakeOneGrid) {
    test::TempDir dir;
    const int n = 11;
    std::vector<int16_t> west = heightsOf(n), east(west.size(), 0), north(west.size(), 0);
    for (size_t k = 0; k < east.size(); ++k) {
        east[k] = static_cast<int16_t>(5000 + k);
        north[k] = static_cast<int16_t>(7000 + k);
    }
    writeHgt(dir.file("N46W122.hgt"), west);
    writeHgt(dir.file("N46W121.hgt"), east);
    writeHgt(dir.file("N47W122.hgt"), north);
    const auto mosaic = RasterSource::openMosaic(
        expandInputs({dir.path()}).paths, 64); // the directory's .hgt files, by name
    const RasterInfo& info = mosaic->info();
    // Two cells a side, sharing their edge samples: 2 n - 1.
    ASSERT_EQ(info.width, 2 * n - 1);
    ASSERT_EQ(info.height, 2 * n - 1);
    const std::vector<float> v = samplesOf(*mosaic);
    const auto at = [&](int x, int y) { return v[static_cast<size_t>(y * info.width + x)]; };
    // South-west cell: rows n-1 .. 2n-2, columns 0 .. n-1; its east edge is the first file's
    // (N46W121 sorts first) where both hold it.
    EXPECT_EQ(at(1, n), static_cast<float>(west[static_cast<size_t>(1 * n + 1)]));
    EXPECT_EQ(at(n - 1, n), static_cast<float>(east[static_cast<size_t>(1 * n + 0)]));
    EXPECT_EQ(at(n + 2, n + 3), static_cast<float>(east[static_cast<size_t>(4 * n + 3)]));
    EXPECT_EQ(at(2, 3), static_cast<float>(north[static_cast<size_t>(3 * n + 2)]));
    // The north-east cell is in no file.
    ASSERT_TRUE(info.nodata.has_value());
    EXPECT_EQ(at(2 * n - 2, 0), static_cast<float>(*info.nodata));
}

} // namespace
} // namespace pyramid
