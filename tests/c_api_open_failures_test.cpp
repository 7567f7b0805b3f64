// The C API's opens when they fail: callbacks are released when the handle that took them closes,
// never after a failed open, and a region's failing callback is named; every open refuses a bad
// argument naming the call, a bad file naming the file, and leaves the handle null.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "formats/ortho_file.hpp"
#include "libpyramid/capi/pyramid.h"
#include "tests/support/c_api_sources.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using test::bytesOf;
using test::ioSource;
using test::MemoryIo;
using test::pathSource;
using test::writeResidualSet;

// Callbacks are released when the handle that took them closes, never after a failed open; a
// region's failing callback is named in the message.
TEST(CApiSources, CallbackOwnershipAndFailures) {
    test::TempDir dir;
    writeResidualSet(dir);
    MemoryIo main, region;
    main.data = bytesOf(dir.file("main.dat"));
    region.data = bytesOf(dir.file("a.dat"));
    const pyramid_source mainSource = ioSource(main, "pak:main");
    const pyramid_source regionSource = ioSource(region, "pak:region-a");
    const pyramid_source* regions[] = {&regionSource};
    pyramid_elevation_options options{};
    options.struct_size = sizeof options;
    options.tile_size = 7; // not 4 / 2^k: refused after the sources were read
    pyramid_elevation* e = nullptr;
    EXPECT_EQ(pyramid_elevation_open_sources(&mainSource, regions, 1, &options, &e), PYRAMID_ERROR_ARGUMENT);
    EXPECT_EQ(e, nullptr);
    EXPECT_EQ(main.released.load() + region.released.load(), 0);
    // The region's table cannot be read.
    options.tile_size = 4;
    region.failAt = 2;
    EXPECT_EQ(pyramid_elevation_open_sources(&mainSource, regions, 1, &options, &e), PYRAMID_ERROR_FILE);
    EXPECT_NE(std::string(pyramid_last_error()).find("pak:region-a"), std::string::npos) << pyramid_last_error();
    EXPECT_EQ(main.released.load() + region.released.load(), 0);
    // A region that is no region of this pyramid (a second main file).
    const pyramid_source* wrong[] = {&mainSource};
    EXPECT_EQ(pyramid_elevation_open_sources(&mainSource, wrong, 1, &options, &e), PYRAMID_ERROR_FILE);
    EXPECT_EQ(main.released.load(), 0);
    region.failAt = 0;
    ASSERT_EQ(pyramid_elevation_open_sources(&mainSource, regions, 1, &options, &e), PYRAMID_OK) << pyramid_last_error();
    std::vector<float> zf(81);
    // A failure while producing a region tile.
    region.failAt = region.reads.load() + 1;
    EXPECT_EQ(pyramid_elevation_tile(e, 1, 1, 1, zf.data(), nullptr, nullptr, zf.size()), PYRAMID_ERROR_FILE);
    EXPECT_NE(std::string(pyramid_last_error()).find("pak:region-a"), std::string::npos) << pyramid_last_error();
    EXPECT_EQ(pyramid_elevation_tile(e, 1, 0, 0, zf.data(), nullptr, nullptr, zf.size()), PYRAMID_OK);
    EXPECT_EQ(main.released.load() + region.released.load(), 0);
    pyramid_elevation_close(e);
    EXPECT_EQ(main.released.load(), 1);
    EXPECT_EQ(region.released.load(), 1);
    // A null region in the array.
    const pyramid_source* missing[] = {nullptr};
    EXPECT_EQ(pyramid_elevation_open_sources(&mainSource, missing, 1, &options, &e), PYRAMID_ERROR_ARGUMENT);
    EXPECT_EQ(pyramid_elevation_open_sources(&mainSource, nullptr, 1, &options, &e), PYRAMID_ERROR_ARGUMENT);
    EXPECT_EQ(main.released.load(), 1);
}

// The three opens of each producer (a path or set, paths, sources) keep one protocol: a bad
// argument is refused with a message naming the call, a bad file with one naming the file, and
// the handle is null after every failed open, whatever it held before.
TEST(CApiSources, EveryOpenClearsTheHandleAndNamesTheCallOrFileWhenItFails) {
    test::TempDir dir;
    writeResidualSet(dir);
    OrthoHeader h;
    h.maxLevel = 0;
    h.tileSize = 8;
    h.channels = 3;
    {
        OrthoFileWriter w(dir.file("rgb.dat"), h);
        w.writeTile(0, 0, 0, std::vector<uint8_t>(12 * 12 * 3, 9));
        w.commit();
    }
    const std::string dem = dir.file("main.dat"), rgb = dir.file("rgb.dat"), none = dir.file("none.dat");
    const pyramid_source demSource = pathSource(dem), rgbSource = pathSource(rgb);
    const char* nullRegion[] = {nullptr};
    // `handle` by reference: read after the call, which the arguments' evaluation may precede.
    const auto refused = [](pyramid_status status, pyramid_status expected, const auto& handle,
                            const std::string& text) {
        EXPECT_EQ(status, expected) << pyramid_last_error();
        EXPECT_TRUE(handle == nullptr);
        EXPECT_NE(std::string(pyramid_last_error()).find(text), std::string::npos) << pyramid_last_error();
    };
    // A handle that held something before the call (never dereferenced).
    int before = 0;
    auto* const staleElevation = reinterpret_cast<pyramid_elevation*>(&before);
    auto* const staleOrtho = reinterpret_cast<pyramid_ortho*>(&before);

    pyramid_elevation* e = staleElevation;
    refused(pyramid_elevation_open(nullptr, 4, 0, 2, &e), PYRAMID_ERROR_ARGUMENT, e,
            "pyramid_elevation_open: null argument");
    refused(pyramid_elevation_open(dem.c_str(), 4, 0, 2, nullptr), PYRAMID_ERROR_ARGUMENT, nullptr,
            "pyramid_elevation_open: null argument");
    e = staleElevation;
    refused(pyramid_elevation_open(none.c_str(), 4, 0, 2, &e), PYRAMID_ERROR_FILE, e, "none.dat");
    e = staleElevation;
    refused(pyramid_elevation_open_regions(dem.c_str(), nullRegion, 1, 4, 0, 2, &e), PYRAMID_ERROR_ARGUMENT, e,
            "pyramid_elevation_open_regions: null argument");
    e = staleElevation;
    refused(pyramid_elevation_open_regions(dem.c_str(), nullptr, 1, 4, 0, 2, &e), PYRAMID_ERROR_ARGUMENT, e,
            "pyramid_elevation_open_regions: null argument");
    refused(pyramid_elevation_open_regions(dem.c_str(), nullptr, 0, 4, 0, 2, nullptr), PYRAMID_ERROR_ARGUMENT,
            nullptr, "pyramid_elevation_open_regions: null argument");
    pyramid_elevation_options eo{};
    eo.struct_size = 1;
    e = staleElevation;
    refused(pyramid_elevation_open_sources(&demSource, nullptr, 0, &eo, &e), PYRAMID_ERROR_ARGUMENT, e,
            "pyramid_elevation_open_sources: options: struct_size 1 is too small");
    refused(pyramid_elevation_open_sources(&demSource, nullptr, 0, nullptr, nullptr), PYRAMID_ERROR_ARGUMENT, nullptr,
            "pyramid_elevation_open_sources: null argument");
    e = staleElevation;
    refused(pyramid_elevation_open_sources(nullptr, nullptr, 0, nullptr, &e), PYRAMID_ERROR_ARGUMENT, e,
            "pyramid_elevation_open_sources: null source");
    ASSERT_EQ(pyramid_elevation_open(dem.c_str(), 4, 0, 2, &e), PYRAMID_OK) << pyramid_last_error();
    EXPECT_EQ(pyramid_elevation_side(e), 9);
    pyramid_elevation_close(e);

    pyramid_ortho* o = staleOrtho;
    refused(pyramid_ortho_open(nullptr, 0, 2, &o), PYRAMID_ERROR_ARGUMENT, o, "pyramid_ortho_open: null argument");
    refused(pyramid_ortho_open(rgb.c_str(), 0, 2, nullptr), PYRAMID_ERROR_ARGUMENT, nullptr,
            "pyramid_ortho_open: null argument");
    o = staleOrtho;
    refused(pyramid_ortho_open(none.c_str(), 0, 2, &o), PYRAMID_ERROR_FILE, o, "none.dat");
    o = staleOrtho;
    refused(pyramid_ortho_open_regions(rgb.c_str(), nullRegion, 1, 0, 2, &o), PYRAMID_ERROR_ARGUMENT, o,
            "pyramid_ortho_open_regions: null argument");
    o = staleOrtho;
    refused(pyramid_ortho_open_regions(rgb.c_str(), nullptr, 0, 2, 2, &o), PYRAMID_ERROR_ARGUMENT, o,
            "pyramid_ortho_open_regions: colour_residuals 2 is neither 0 nor 1");
    pyramid_ortho_options oo{};
    oo.struct_size = 1;
    o = staleOrtho;
    refused(pyramid_ortho_open_sources(&rgbSource, nullptr, 0, &oo, &o), PYRAMID_ERROR_ARGUMENT, o,
            "pyramid_ortho_open_sources: options: struct_size 1 is too small");
    refused(pyramid_ortho_open_sources(&rgbSource, nullptr, 0, nullptr, nullptr), PYRAMID_ERROR_ARGUMENT, nullptr,
            "pyramid_ortho_open_sources: null argument");
    o = staleOrtho;
    refused(pyramid_ortho_open_sources(&demSource, nullptr, 0, nullptr, &o), PYRAMID_ERROR_FILE, o, "main.dat");
    ASSERT_EQ(pyramid_ortho_open(rgb.c_str(), 1, 2, &o), PYRAMID_OK) << pyramid_last_error();
    int side = 0, channels = 0;
    EXPECT_EQ(pyramid_ortho_layout(o, &side, &channels), PYRAMID_OK);
    EXPECT_EQ(side, 12);
    EXPECT_EQ(channels, 3);
    pyramid_ortho_close(o);
}

} // namespace
} // namespace pyramid
