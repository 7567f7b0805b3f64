// The elevation producer's scale option, in the C API and the C++ residual producer: each file's
// residuals times (its scale x the option's), the product in float32, against a reference built
// from the residuals the files hold; non-finite and zero scales refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/capi/pyramid.h"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "libpyramid/runtime/residual_producer.hpp"
#include "tests/support/c_api_sources.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using test::pathSource;
using test::writeResidualSet;

// The scale option: each file's residuals times (its scale x the option's), the product in
// float32, against a reference built from the residuals the files hold.
TEST(CApiSources, ScaleMultipliesEveryFilesResiduals) {
    test::TempDir dir;
    writeResidualSet(dir);
    const std::string mainPath = dir.file("main.dat"), aPath = dir.file("a.dat");
    const pyramid_source mainSource = pathSource(mainPath), aSource = pathSource(aPath);
    const pyramid_source* regions[] = {&aSource};
    const float scale = 3.0f;
    pyramid_elevation_options options{};
    options.struct_size = sizeof options;
    options.tile_size = 4; // delta 1: producer level l is file level l + 1
    options.cache_tiles = 8;
    options.scale = scale;
    pyramid_elevation* e = nullptr;
    ASSERT_EQ(pyramid_elevation_open_sources(&mainSource, regions, 1, &options, &e), PYRAMID_OK) << pyramid_last_error();

    const auto mainFile = ResidualFileReader::open(mainPath);
    const auto aFile = ResidualFileReader::open(aPath);
    auto scaled = [](const std::vector<int16_t>& r, float s) {
        std::vector<float> out(r.size());
        for (size_t k = 0; k < r.size(); ++k) {
            out[k] = static_cast<float>(r[k]) * s;
        }
        return out;
    };
    const float mainScale = 0.5f * scale, aScale = 0.25f * scale;
    // Root: file levels 0 (5 x 5 samples, in the corner of the 9 x 9 array) and 1, upsampled
    // and added.
    std::vector<float> level0(81, 0.0f);
    const std::vector<float> r0 = scaled(mainFile->readTile(0, 0, 0), mainScale);
    for (int j = 0; j < 7; ++j) {
        for (int i = 0; i < 7; ++i) {
            level0[static_cast<size_t>(i + 9 * j)] = r0[static_cast<size_t>(i + 7 * j)];
        }
    }
    ASSERT_EQ(mainFile->header().tileSamples(0), 7);
    std::vector<float> root = scaled(mainFile->readTile(1, 0, 0), mainScale);
    upsampleAndAdd(level0.data(), 9, 4, 1, 1, root.data(), 9);
    std::vector<float> zf(81);
    ASSERT_EQ(pyramid_elevation_tile(e, 0, 0, 0, zf.data(), nullptr, nullptr, 81), PYRAMID_OK) << pyramid_last_error();
    EXPECT_EQ(zf, root);
    // (1, 1, 1) is region A's root at A's scale; (1, 0, 1) the main file's level 2.
    std::vector<float> a = scaled(aFile->readTile(0, 0, 0), aScale);
    upsampleAndAdd(root.data(), 9, 4, quadrantOffset(1, 4), quadrantOffset(1, 4), a.data(), 9);
    ASSERT_EQ(pyramid_elevation_tile(e, 1, 1, 1, zf.data(), nullptr, nullptr, 81), PYRAMID_OK);
    EXPECT_EQ(zf, a);
    std::vector<float> m = scaled(mainFile->readTile(2, 0, 1), mainScale);
    upsampleAndAdd(root.data(), 9, 4, quadrantOffset(0, 4), quadrantOffset(1, 4), m.data(), 9);
    ASSERT_EQ(pyramid_elevation_tile(e, 1, 0, 1, zf.data(), nullptr, nullptr, 81), PYRAMID_OK);
    EXPECT_EQ(zf, m);
    // The height query goes through the same tiles.
    double height = 0.0;
    ASSERT_EQ(pyramid_elevation_height(e, 1, 0.75, 0.75, &height), PYRAMID_OK);
    EXPECT_EQ(height, static_cast<double>(a[4 + 9 * 4]));
    pyramid_elevation_close(e);

    // Without the option (or with 0, its default) the files' own scales.
    options.scale = 0.0f;
    ASSERT_EQ(pyramid_elevation_open_sources(&mainSource, regions, 1, &options, &e), PYRAMID_OK);
    ASSERT_EQ(pyramid_elevation_tile(e, 0, 0, 0, zf.data(), nullptr, nullptr, 81), PYRAMID_OK);
    EXPECT_NE(zf, root);
    EXPECT_NEAR(zf[40] * scale, root[40], 1e-3f * std::abs(root[40]));
    pyramid_elevation_close(e);
    // A negative scale mirrors the heights; infinity is refused.
    options.scale = -1.0f;
    ASSERT_EQ(pyramid_elevation_open_sources(&mainSource, regions, 1, &options, &e), PYRAMID_OK);
    std::vector<float> mirrored(81);
    ASSERT_EQ(pyramid_elevation_tile(e, 0, 0, 0, mirrored.data(), nullptr, nullptr, 81), PYRAMID_OK);
    EXPECT_EQ(mirrored[40], -zf[40]);
    pyramid_elevation_close(e);
    options.scale = std::numeric_limits<float>::infinity();
    EXPECT_EQ(pyramid_elevation_open_sources(&mainSource, regions, 1, &options, &e), PYRAMID_ERROR_ARGUMENT);
}

TEST(ResidualProducerScale, RefusesNonFiniteAndZero) {
    ResidualProducerOptions o;
    EXPECT_NO_THROW(o.validate());
    o.scale = 0.0f;
    EXPECT_THROW(o.validate(), OptionError);
    o.scale = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(o.validate(), OptionError);
}

} // namespace
} // namespace pyramid
