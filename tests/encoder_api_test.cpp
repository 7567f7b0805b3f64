// The encoders as a library (libpyramid/api/encoders.hpp): a caller's own sources give the
// bytes files give, a procedural planet verifies against its function, and a cancelled run
// leaves nothing behind.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "libpyramid/api/encoders.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::readFile;
using test::TempDir;

// Counts its reads, to show that the encoder went through it.
class CountingHeights final : public ElevationSource {
public:
    CountingHeights(const std::vector<float>& h, int w, int ht) : h_(h), w_(w), ht_(ht) {}
    int width() const override { return w_; }
    int height() const override { return ht_; }
    void read(int x0, int y0, int x1, int y1, float* out) const override {
        ++reads;
        for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
                *out++ = h_[static_cast<size_t>(y) * static_cast<size_t>(w_) + static_cast<size_t>(x)];
            }
        }
    }
    std::string name() const override { return "counting"; }
    mutable std::atomic<int64_t> reads{0};

private:
    const std::vector<float>& h_;
    int w_, ht_;
};

TEST(EncoderApi, ElevationSourcesGiveTheFileBytes) {
    TempDir dir;
    const int w = 203, h = 157;
    std::vector<float> heights = test::syntheticHeights(w, h, 1500.0f);
    heights[5000] = -9999.0f; // nodata, declared below
    const std::string tif = dir.file("in.tif");
    test::writeFloatRaster(tif, w, h, heights);
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 8;
    o.scale = 0.5;
    o.nodata = -9999.0;
    const DemReport fromFile = encodeDem(tif, dir.file("file.dat"), o);
    const DemReport fromArray = encodeDem(ElevationArray(heights, w, h), dir.file("array.dat"), o);
    CountingHeights counting(heights, w, h);
    o.threads = 1;
    const DemReport fromCallback = encodeDem(counting, dir.file("callback.dat"), o);
    const std::string expected = readFile(dir.file("file.dat"));
    EXPECT_GT(expected.size(), 1000u);
    EXPECT_EQ(readFile(dir.file("array.dat")), expected);
    EXPECT_EQ(readFile(dir.file("callback.dat")), expected);
    EXPECT_GT(counting.reads.load(), 0);
    EXPECT_EQ(fromArray.nodataFilled, fromFile.nodataFilled);
    EXPECT_GT(fromArray.nodataFilled, 0);
    EXPECT_EQ(fromArray.input, "array");
    EXPECT_FALSE(fromArray.georeference);

    // The same source, verified: within the bound, and not against other heights.
    DemVerifyOptions v;
    v.nodata = -9999.0;
    EXPECT_TRUE(verifyDem(dir.file("array.dat"), ElevationArray(heights, w, h), v).ok());
    std::vector<float> other = heights;
    other[7000] += 10.0f;
    EXPECT_FALSE(verifyDem(dir.file("array.dat"), ElevationArray(other, w, h), v).ok());
}

TEST(EncoderApi, ColourSourcesGiveTheFileBytes) {
    TempDir dir;
    const int w = 150, h = 90, channels = 3;
    std::vector<uint16_t> values(static_cast<size_t>(w * h * channels));
    std::vector<uint8_t> bytes(values.size());
    for (size_t k = 0; k < values.size(); ++k) {
        bytes[k] = static_cast<uint8_t>((k * 7919u + (k / 3) * 13u) % 251u);
        values[k] = bytes[k];
    }
    test::writeImage(dir.file("in.tif"), w, h, channels, values, false);
    OrthoEncodeOptions o;
    o.levels.tileSize = 32;
    encodeOrtho(dir.file("in.tif"), dir.file("file"), o);
    encodeOrtho(ColourArray(bytes, w, h, channels), dir.file("array"), o);
    for (const char* out : {"RGB.dat", "dxt/RGB.dat", "residuals/RGB.dat"}) {
        const std::string expected = readFile(dir.file("file/") + out);
        EXPECT_GT(expected.size(), 500u) << out;
        EXPECT_EQ(readFile(dir.file("array/") + out), expected) << out;
    }
}

TEST(EncoderApi, ArraysOfTheWrongSizeAreRefused) {
    std::vector<float> heights(10);
    EXPECT_THROW(ElevationArray(heights, 4, 3), Error);
    std::vector<uint8_t> pixels(12);
    EXPECT_THROW(ColourArray(pixels, 2, 2, 5), Error);
    EXPECT_NO_THROW(ColourArray(pixels, 2, 2, 3));
}

// A planet of hills: a smooth function of the direction, in metres.
double hills(double lat, double lon) {
    const double p = lat * M_PI / 180.0, l = lon * M_PI / 180.0;
    const double x = std::cos(p) * std::cos(l), y = std::cos(p) * std::sin(l), z = std::sin(p);
    return 800.0 * std::sin(3.0 * x + 1.0) * std::cos(2.0 * y) + 300.0 * z * z - 150.0 * x * y;
}

TEST(EncoderApi, AProceduralPlanetVerifiesAgainstItsFunction) {
    TempDir dir;
    const PlanetFunction planet(hills, 256, "hills");
    SphericalDemOptions o;
    o.dem.tileSize = 16;
    o.dem.rootTileSize = 4;
    o.dem.scale = 0.25;
    o.body = "sphere";
    o.dem.threads = 2;
    const SphericalDemReport report = encodeSphericalDem(planet, dir.file("two"), o);
    ASSERT_EQ(report.faces.size(), 6u);
    EXPECT_EQ(report.faces[0].dem.header.maxLevel, 4); // 4 << 4 = 64 = 256 / 4
    o.dem.threads = 1;
    encodeSphericalDem(planet, dir.file("one"), o);
    for (int f = 1; f <= 6; ++f) {
        const std::string name = "/DEM" + std::to_string(f) + ".dat";
        EXPECT_EQ(readFile(dir.file("one") + name), readFile(dir.file("two") + name)) << name;
    }
    SphericalDemVerifyOptions v;
    v.body = "sphere";
    const std::vector<DemVerifyReport> checked = verifySphericalDem(dir.file("two"), planet, v);
    ASSERT_EQ(checked.size(), 6u);
    for (const DemVerifyReport& r : checked) {
        EXPECT_TRUE(r.ok()) << r.file;
        EXPECT_EQ(r.source, "hills");
        EXPECT_GT(r.levels.back().samples, 60 * 60);
    }
    // Another planet does not pass.
    const PlanetFunction other([](double lat, double lon) { return hills(lat, lon) + (lat > 30.0 ? 5.0 : 0.0); }, 256);
    bool anyFails = false;
    for (const DemVerifyReport& r : verifySphericalDem(dir.file("two"), other, v)) {
        anyFails = anyFails || !r.ok();
    }
    EXPECT_TRUE(anyFails);
}

TEST(EncoderApi, AColourPlanetWritesSixFaces) {
    // Three channels, as a function of the position: sea blue below the equator, land above.
    class Colours final : public PlanetSource {
    public:
        int channels() const override { return 3; }
        int resolution() const override { return 128; }
        void read(const GeodeticPoint* p, size_t n, float* out, uint8_t* valid) const override {
            for (size_t k = 0; k < n; ++k) {
                const bool land = p[k].latitude > 0.0;
                out[3 * k] = land ? 120.0f : 10.0f;
                out[3 * k + 1] = land ? 200.0f : 40.0f;
                out[3 * k + 2] = land ? 30.0f : 220.0f;
                valid[k] = 1;
            }
        }
    } planet;
    TempDir dir;
    SphericalOrthoOptions o;
    o.ortho.levels.tileSize = 16;
    o.ortho.writeDxt = false;
    o.ortho.writeResiduals = false;
    const SphericalOrthoReport report = encodeSphericalOrtho(planet, dir.path(), o);
    ASSERT_EQ(report.faces.size(), 6u);
    EXPECT_EQ(report.faces[0].ortho.maxLevel, 1); // 16 << 1 = 32 = 128 / 4
    for (int f = 1; f <= 6; ++f) {
        EXPECT_TRUE(test::fileExists(dir.file("RGB" + std::to_string(f) + ".dat")));
    }
}

TEST(EncoderApi, ACancelledRunLeavesNothing) {
    TempDir dir;
    const int w = 129, h = 129;
    const std::vector<float> heights = test::syntheticHeights(w, h);
    DemEncodeOptions o;
    o.tileSize = 16;
    o.rootTileSize = 4;
    int64_t seen = 0;
    o.progress = [&](int64_t done, int64_t) { seen = done; };
    o.cancelled = [&] { return seen >= 3; };
    EXPECT_THROW(encodeDem(ElevationArray(heights, w, h), dir.file("DEM.dat"), o), Cancelled);
    EXPECT_EQ(seen, 3);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));

    std::vector<uint8_t> pixels(static_cast<size_t>(w * h * 3), 77);
    OrthoEncodeOptions oo;
    oo.levels.tileSize = 16;
    int64_t tiles = 0;
    oo.progress = [&](int64_t done, int64_t) { tiles = done; };
    oo.cancelled = [&] { return tiles >= 2; };
    EXPECT_THROW(encodeOrtho(ColourArray(pixels, w, h, 3), dir.file("ortho"), oo), Cancelled);
    EXPECT_FALSE(std::filesystem::exists(dir.file("ortho/RGB.dat")));
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir.path())) {
        EXPECT_TRUE(e.is_directory()) << e.path(); // no file, temporary or not
    }
}

TEST(EncoderApi, CallerSourcesTakeNoTarget) {
    const std::vector<float> heights(16, 1.0f);
    DemEncodeOptions o;
    o.target.crs = "EPSG:4326";
    EXPECT_THROW(encodeDem(ElevationArray(heights, 4, 4), "/nonexistent/x.dat", o), OptionError);
}

} // namespace
} // namespace pyramid
