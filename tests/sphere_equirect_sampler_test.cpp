// Sampling equirectangular rasters by latitude and longitude: pixel centres, wrap-around,
// pole clamping, partial extents, nodata, and the two read paths (one window, point by point).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

// A W x H float raster whose pixel (i, j) holds 1000 j + i (row 0 north).
std::string writeRaster(const test::TempDir& dir, int W, int H, float nodataAt = -1.0f) {
    std::vector<float> v(static_cast<size_t>(W) * H);
    for (int j = 0; j < H; ++j) {
        for (int i = 0; i < W; ++i) {
            v[static_cast<size_t>(i + j * W)] = static_cast<float>(1000 * j + i);
        }
    }
    if (nodataAt >= 0) {
        v[static_cast<size_t>(nodataAt)] = -9999.0f;
    }
    const std::string path = dir.file("map.tif");
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec spec(W, H, 1, OIIO::TypeDesc::FLOAT);
    EXPECT_TRUE(out->open(path, spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, v.data()));
    out->close();
    return path;
}

struct Sampled {
    float value;
    bool valid;
};

Sampled sampleOne(const EquirectSampler& s, double lat, double lon) {
    const GeodeticPoint p{lat, lon};
    float v = -1;
    uint8_t ok = 7;
    s.sample(&p, 1, &v, &ok);
    return {v, ok == 1};
}

TEST(EquirectSampler, PixelCentresWrapAndPoles) {
    test::TempDir dir;
    const auto src = RasterSource::open(writeRaster(dir, 36, 18)); // 10-degree pixels
    const EquirectSampler s(*src, GeoExtent{}, 0, 1, SampleRead::Float, std::nullopt);
    // Pixel (i, j) is centred on longitude -175 + 10 i, latitude 85 - 10 j.
    EXPECT_EQ(sampleOne(s, 85, -175).value, 0.0f);
    EXPECT_EQ(sampleOne(s, 85 - 10 * 7, -175 + 10 * 20).value, 7020.0f);
    EXPECT_EQ(sampleOne(s, -85, 175).value, 17035.0f);
    // Halfway between two centres in longitude, and the same point one turn away.
    EXPECT_EQ(sampleOne(s, 85, -170).value, 0.5f);
    EXPECT_EQ(sampleOne(s, 85, 190).value, 0.5f);
    // Longitude +-180 lies between the last and the first column: wrap-around.
    EXPECT_EQ(sampleOne(s, 85, 180).value, 17.5f);
    EXPECT_EQ(sampleOne(s, 85, -180).value, 17.5f);
    // North of the first row of centres: clamped to it; the pole itself too.
    EXPECT_EQ(sampleOne(s, 88, -175).value, 0.0f);
    EXPECT_EQ(sampleOne(s, 90, -175).value, 0.0f);
    EXPECT_EQ(sampleOne(s, -90, -175).value, 17000.0f);
    // Bilinear in both directions.
    EXPECT_FLOAT_EQ(sampleOne(s, 82.5, -172.5).value, 250.25f);
}

// Points many turns of longitude apart, sampled in one call and alone, read the columns of their
// longitude modulo 360: across the antimeridian (the last column's east neighbour is the first),
// and for longitudes up to five turns away either way.
TEST(EquirectSampler, LongitudesWrapByAnyNumberOfTurns) {
    test::TempDir dir;
    const auto src = RasterSource::open(writeRaster(dir, 36, 18)); // 10-degree pixels
    const EquirectSampler s(*src, GeoExtent{}, 0, 1, SampleRead::Float, std::nullopt);
    std::vector<GeodeticPoint> points;
    std::vector<float> expected;
    for (int turn = -5; turn <= 5; ++turn) {
        for (int i = 0; i < 36; ++i) {
            // Row 2's centres, a quarter of the way from column i to its east neighbour and to its
            // west neighbour (wrapping).
            const float here = static_cast<float>(2000 + i), east = static_cast<float>(2000 + (i + 1) % 36),
                        west = static_cast<float>(2000 + (i + 35) % 36);
            points.push_back({85.0 - 20.0, -175.0 + 10.0 * i + 2.5 + 360.0 * turn});
            expected.push_back(here + (east - here) * 0.25f);
            points.push_back({85.0 - 20.0, -175.0 + 10.0 * i - 2.5 + 360.0 * turn});
            expected.push_back(west + (here - west) * 0.75f);
        }
    }
    std::vector<float> batch(points.size(), -1.0f);
    std::vector<uint8_t> valid(points.size(), 0);
    s.sample(points.data(), points.size(), batch.data(), valid.data());
    for (size_t k = 0; k < points.size(); ++k) {
        SCOPED_TRACE(points[k].longitude);
        EXPECT_EQ(valid[k], 1);
        EXPECT_FLOAT_EQ(batch[k], expected[k]);
        EXPECT_EQ(sampleOne(s, points[k].latitude, points[k].longitude).value, batch[k]);
    }
}

TEST(EquirectSampler, PartialExtentIsNodataOutside) {
    test::TempDir dir;
    const auto src = RasterSource::open(writeRaster(dir, 20, 10));
    // 1-degree pixels over longitudes 10..30, latitudes 40..50.
    const EquirectSampler s(*src, GeoExtent::parse("10,40,30,50"), 0, 1, SampleRead::Float, std::nullopt);
    EXPECT_EQ(sampleOne(s, 49.5, 10.5).value, 0.0f);
    EXPECT_TRUE(sampleOne(s, 50.0, 10.0).valid); // edges of the extent: clamped to the nearest centres
    EXPECT_EQ(sampleOne(s, 50.0, 10.0).value, 0.0f);
    EXPECT_EQ(sampleOne(s, 40.0, 30.0).value, 9019.0f);
    EXPECT_FALSE(sampleOne(s, 50.01, 20).valid);
    EXPECT_FALSE(sampleOne(s, 45, 9.99).valid);
    EXPECT_FALSE(sampleOne(s, 45, 30.01).valid);
    EXPECT_FALSE(sampleOne(s, -45, -160).valid);
    EXPECT_EQ(sampleOne(s, 45.5, 20.5 - 360).value, 4010.0f); // longitudes are taken modulo 360
}

TEST(EquirectSampler, ExtentAcrossTheAntimeridian) {
    test::TempDir dir;
    const auto src = RasterSource::open(writeRaster(dir, 20, 10));
    const EquirectSampler s(*src, GeoExtent::parse("170,0,190,10"), 0, 1, SampleRead::Float, std::nullopt);
    EXPECT_EQ(sampleOne(s, 9.5, 170.5).value, 0.0f);
    EXPECT_EQ(sampleOne(s, 9.5, -170.5).value, 19.0f);
    EXPECT_FALSE(sampleOne(s, 5, -169).valid);
}

TEST(EquirectSampler, NodataPixelsSpoilOnlyTheirNeighbourhood) {
    test::TempDir dir;
    const auto src = RasterSource::open(writeRaster(dir, 36, 18, 5 + 36 * 3)); // pixel (5, 3)
    const EquirectSampler s(*src, GeoExtent{}, 0, 1, SampleRead::Float, -9999.0);
    const double lon5 = -175 + 50, lat3 = 85 - 30;
    EXPECT_FALSE(sampleOne(s, lat3, lon5).valid);
    EXPECT_FALSE(sampleOne(s, lat3 + 5, lon5 + 5).valid);
    EXPECT_TRUE(sampleOne(s, lat3, lon5 + 10).valid); // the next centre: zero weight on (5, 3)
    EXPECT_EQ(sampleOne(s, lat3, lon5 + 10).value, 3006.0f);
    const EquirectSampler noNodata(*src, GeoExtent{}, 0, 1, SampleRead::Float, std::nullopt);
    EXPECT_EQ(sampleOne(noNodata, lat3, lon5).value, -9999.0f);
}

TEST(EquirectSampler, OneWindowAndPointByPointAgree) {
    test::TempDir dir;
    const auto src = RasterSource::open(writeRaster(dir, 1024, 512));
    const EquirectSampler s(*src, GeoExtent{}, 0, 1, SampleRead::Float, std::nullopt);
    // Scattered over the globe (too sparse for one window) and clustered (one window).
    std::vector<GeodeticPoint> scattered, clustered;
    for (int k = 0; k < 50; ++k) {
        scattered.push_back({-89.0 + 3.56 * k, -179.9 + 7.3 * k});
        clustered.push_back({10.0 + 0.013 * k, 179.5 + 0.021 * k}); // across the antimeridian
    }
    for (const auto* points : {&scattered, &clustered}) {
        std::vector<float> batch(points->size());
        std::vector<uint8_t> valid(points->size());
        s.sample(points->data(), points->size(), batch.data(), valid.data());
        for (size_t k = 0; k < points->size(); ++k) {
            const Sampled one = sampleOne(s, (*points)[k].latitude, (*points)[k].longitude);
            EXPECT_TRUE(valid[k]);
            EXPECT_EQ(batch[k], one.value) << k;
        }
    }
}

TEST(EquirectSampler, BadExtentsAndChannels) {
    for (const char* text : {"", "1,2,3", "10,0,5,10", "0,10,10,5", "0,-91,10,0", "-180,0,190,10", "a,b,c,d",
                             "1,2,3,4,5"}) {
        EXPECT_THROW(GeoExtent::parse(text), Error) << text;
    }
    test::TempDir dir;
    const auto src = RasterSource::open(writeRaster(dir, 4, 2));
    EXPECT_THROW(EquirectSampler(*src, GeoExtent{}, 1, 2, SampleRead::Float, std::nullopt), Error);
}

// One rule for an extent, parsed from text or given as numbers: OptionError("extent") with the
// broken rule (and the text it came from).
TEST(EquirectSampler, ExtentRuleOnceForTextAndNumbers) {
    const auto problem = [](const auto& check) -> std::string {
        try {
            check();
        } catch (const OptionError& e) {
            EXPECT_EQ(e.option(), "extent");
            return e.problem();
        }
        return "no error";
    };
    EXPECT_EQ(problem([] { GeoExtent::parse("10,0,5,10"); }), "needs WEST < EAST <= WEST + 360, not 10,0,5,10");
    EXPECT_EQ(problem([] { GeoExtent{0, -100, 10, 0}.validate(); }), "needs -90 <= SOUTH < NORTH <= 90");
    EXPECT_EQ(problem([] { GeoExtent::parse("0,x,1,1"); }), "'x' is not a number of degrees");
    EXPECT_EQ(problem([] { GeoExtent{}.validate(); }), "no error");
    try {
        GeoExtent::parse("0,10,10,5");
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "extent: needs -90 <= SOUTH < NORTH <= 90, not 0,10,10,5");
    }
}

} // namespace
} // namespace pyramid
