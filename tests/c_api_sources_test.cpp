// The C API's other opens: memory and I/O callbacks give what paths give, on the original tools'
// files and on region sets; the elevation producer's scale against residuals; the ownership of
// the callbacks.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/capi/pyramid.h"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "libpyramid/runtime/residual_producer.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

std::vector<uint8_t> bytesOf(const std::string& path) {
    const std::string text = test::readFile(path);
    return std::vector<uint8_t>(text.begin(), text.end());
}

// I/O callbacks over bytes in memory, counting reads and releases; reads fail from the
// `failAt`-th on (0: never).
struct MemoryIo {
    std::vector<uint8_t> data;
    std::atomic<long> reads{0};
    std::atomic<int> released{0};
    long failAt = 0;

    static int read(void* user, uint64_t offset, void* buffer, size_t size, size_t* bytesRead) {
        auto* io = static_cast<MemoryIo*>(user);
        const long n = ++io->reads;
        if ((io->failAt != 0 && n >= io->failAt) || offset > io->data.size() || size > io->data.size() - offset) {
            return 1;
        }
        std::memcpy(buffer, io->data.data() + offset, size);
        *bytesRead = size;
        return 0;
    }
    static void release(void* user) { ++static_cast<MemoryIo*>(user)->released; }
};

pyramid_source pathSource(const std::string& path) {
    pyramid_source s{};
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_PATH;
    s.path = path.c_str();
    return s;
}

pyramid_source memorySource(const std::vector<uint8_t>& bytes, const char* name = nullptr) {
    pyramid_source s{};
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_MEMORY;
    s.name = name;
    s.data = bytes.data();
    s.size = bytes.size();
    return s;
}

pyramid_source ioSource(MemoryIo& io, const char* name) {
    pyramid_source s{};
    s.struct_size = sizeof s;
    s.kind = PYRAMID_SOURCE_IO;
    s.name = name;
    s.io.read = &MemoryIo::read;
    s.io.release = &MemoryIo::release;
    s.io.user = &io;
    s.io.size = io.data.size();
    return s;
}

// One file's tiles, decoded and as stored, each with its status.
std::vector<std::vector<uint8_t>> allTiles(pyramid_file* f) {
    pyramid_info info;
    EXPECT_EQ(pyramid_get_info(f, &info), PYRAMID_OK);
    std::vector<std::vector<uint8_t>> out;
    for (int level = 0; level <= info.max_level; ++level) {
        const int side = info.kind == PYRAMID_KIND_RESIDUAL
                             ? (level < info.min_level ? 1 : 1 << (level - info.min_level))
                             : 1 << level;
        for (int t = 0; t < side * side; ++t) {
            for (int stored = 0; stored < 2; ++stored) {
                size_t size = 0;
                auto read = stored ? pyramid_read_tile_bytes : pyramid_read_tile;
                EXPECT_EQ(read(f, level, t % side, t / side, nullptr, 0, &size), PYRAMID_OK) << pyramid_last_error();
                std::vector<uint8_t> tile(size);
                EXPECT_EQ(read(f, level, t % side, t / side, tile.data(), size, nullptr), PYRAMID_OK);
                out.push_back(std::move(tile));
            }
        }
    }
    return out;
}

// zf, zc and zm of every elevation tile of levels 0..maxLevel.
std::vector<float> allElevations(pyramid_elevation* e, int maxLevel) {
    const size_t n = static_cast<size_t>(pyramid_elevation_side(e)) * pyramid_elevation_side(e);
    std::vector<float> out;
    std::vector<float> z(3 * n);
    for (int level = 0; level <= maxLevel; ++level) {
        for (int t = 0; t < (1 << (2 * level)); ++t) {
            EXPECT_EQ(pyramid_elevation_tile(e, level, t % (1 << level), t / (1 << level), z.data(), z.data() + n,
                                             z.data() + 2 * n, n),
                      PYRAMID_OK)
                << pyramid_last_error();
            out.insert(out.end(), z.begin(), z.end());
        }
    }
    return out;
}

// Every ortho tile of levels 0..maxLevel, an absent tile as its status alone.
std::vector<std::vector<uint8_t>> allOrtho(pyramid_ortho* o, int maxLevel) {
    int side = 0, channels = 0;
    EXPECT_EQ(pyramid_ortho_layout(o, &side, &channels), PYRAMID_OK);
    const size_t bytes = static_cast<size_t>(side) * side * channels;
    std::vector<std::vector<uint8_t>> out;
    for (int level = 0; level <= maxLevel; ++level) {
        for (int t = 0; t < (1 << (2 * level)); ++t) {
            std::vector<uint8_t> tile(bytes);
            const pyramid_status s = pyramid_ortho_tile(o, level, t % (1 << level), t / (1 << level), tile.data(), bytes);
            EXPECT_TRUE(s == PYRAMID_OK || s == PYRAMID_ERROR_NOT_FOUND) << pyramid_last_error();
            out.push_back(s == PYRAMID_OK ? tile : std::vector<uint8_t>{static_cast<uint8_t>(s)});
        }
    }
    return out;
}

TEST(CApiSources, OriginalFilesFromMemoryAndCallbacks) {
    const std::string dem = test::sharedFixturePath("proland/DEM.dat");
    const std::string rgb = test::sharedFixturePath("proland/RGB.dat");
    if (dem.empty() || rgb.empty()) {
        GTEST_SKIP() << "../shared/fixtures is not there";
    }
    for (const std::string& path : {dem, rgb}) {
        const std::vector<uint8_t> bytes = bytesOf(path);
        MemoryIo io;
        io.data = bytes;
        const pyramid_source sources[] = {pathSource(path), memorySource(bytes), ioSource(io, "callbacks")};
        std::vector<std::vector<std::vector<uint8_t>>> tiles;
        for (const pyramid_source& source : sources) {
            pyramid_file* f = nullptr;
            ASSERT_EQ(pyramid_open_source(&source, &f), PYRAMID_OK) << pyramid_last_error();
            tiles.push_back(allTiles(f));
            pyramid_close(f);
        }
        EXPECT_GT(tiles[0].size(), 9u);
        EXPECT_EQ(tiles[1], tiles[0]) << path;
        EXPECT_EQ(tiles[2], tiles[0]) << path;
        EXPECT_GT(io.reads.load(), 0);
        EXPECT_EQ(io.released.load(), 1);
    }
    // The producers: elevations of the file's tile size (delta 3: the root is built from four
    // levels), and the ortho producer with and without colour residuals.
    const std::vector<uint8_t> demBytes = bytesOf(dem), rgbBytes = bytesOf(rgb);
    MemoryIo demIo, rgbIo[2];
    demIo.data = demBytes;
    rgbIo[0].data = rgbIo[1].data = rgbBytes;
    std::vector<std::vector<float>> elevations;
    for (const pyramid_source& source : {pathSource(dem), memorySource(demBytes), ioSource(demIo, "dem")}) {
        pyramid_elevation* e = nullptr;
        ASSERT_EQ(pyramid_elevation_open_sources(&source, nullptr, 0, nullptr, &e), PYRAMID_OK) << pyramid_last_error();
        elevations.push_back(allElevations(e, 3));
        pyramid_elevation_close(e);
    }
    EXPECT_EQ(elevations[1], elevations[0]);
    EXPECT_EQ(elevations[2], elevations[0]);
    for (int colour = 0; colour < 2; ++colour) {
        pyramid_ortho_options options{};
        options.struct_size = sizeof options;
        options.colour_residuals = colour;
        options.cache_tiles = 8;
        std::vector<std::vector<std::vector<uint8_t>>> ortho;
        for (const pyramid_source& source : {pathSource(rgb), memorySource(rgbBytes), ioSource(rgbIo[colour], "rgb")}) {
            pyramid_ortho* o = nullptr;
            ASSERT_EQ(pyramid_ortho_open_sources(&source, nullptr, 0, &options, &o), PYRAMID_OK) << pyramid_last_error();
            ortho.push_back(allOrtho(o, 2));
            pyramid_ortho_close(o);
        }
        EXPECT_EQ(ortho[1], ortho[0]);
        EXPECT_EQ(ortho[2], ortho[0]);
        EXPECT_EQ(rgbIo[colour].released.load(), 1);
    }
}

// Residual tile whose every sample is `base + i + 3 j`.
std::vector<int16_t> ramp(int size, int base) {
    std::vector<int16_t> r(static_cast<size_t>(size) * size);
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            r[static_cast<size_t>(i + j * size)] = static_cast<int16_t>(base + i + 3 * j);
        }
    }
    return r;
}

// A main residual pyramid (levels 0..2, minLevel 1) and two nested regions, each with its own
// scale: A rooted at (2, 1, 1) with levels 2..3, B inside A rooted at (3, 2, 2) with 3..4.
void writeResidualSet(const test::TempDir& dir) {
    auto write = [&](const std::string& name, int rootLevel, int rootTx, int rootTy, int maxLevel, float scale,
                     int base) {
        ResidualHeader h;
        h.minLevel = rootLevel == 0 ? 1 : 0;
        h.maxLevel = maxLevel;
        h.tileSize = 4;
        h.rootLevel = rootLevel;
        h.rootTx = rootTx;
        h.rootTy = rootTy;
        h.scale = scale;
        ResidualFileWriter w(dir.file(name), h);
        for (int l = 0; l <= maxLevel; ++l) {
            const int side = l < h.minLevel ? 1 : 1 << (l - h.minLevel);
            for (int t = 0; t < side * side; ++t) {
                w.writeTile(l, t % side, t / side, ramp(h.tileSamples(l), base + 10 * l + t));
            }
        }
        w.commit();
    };
    write("main.dat", 0, 0, 0, 2, 0.5f, 100);
    write("a.dat", 2, 1, 1, 1, 0.25f, 200);
    write("b.dat", 3, 2, 2, 1, 0.125f, 300);
}

TEST(CApiSources, ResidualRegionSetsFromMemoryAndCallbacks) {
    test::TempDir dir;
    writeResidualSet(dir);
    const std::vector<std::string> names = {dir.file("main.dat"), dir.file("a.dat"), dir.file("b.dat")};
    std::vector<std::vector<uint8_t>> bytes;
    MemoryIo io[3];
    for (size_t k = 0; k < 3; ++k) {
        bytes.push_back(bytesOf(names[k]));
        io[k].data = bytes[k];
    }
    std::vector<std::vector<float>> results;
    for (int how = 0; how < 3; ++how) {
        std::vector<pyramid_source> sources;
        for (size_t k = 0; k < 3; ++k) {
            sources.push_back(how == 0 ? pathSource(names[k]) : how == 1 ? memorySource(bytes[k]) : ioSource(io[k], "r"));
        }
        const pyramid_source* regions[] = {&sources[1], &sources[2]};
        for (const int n : {4, 2}) {
            pyramid_elevation_options options{};
            options.struct_size = sizeof options;
            options.tile_size = n;
            options.cache_tiles = 3;
            pyramid_elevation* e = nullptr;
            ASSERT_EQ(pyramid_elevation_open_sources(&sources[0], regions, 2, &options, &e), PYRAMID_OK)
                << pyramid_last_error();
            results.push_back(allElevations(e, 5));
            pyramid_elevation_close(e);
        }
    }
    // The path open through the 0.2.0 function, for reference.
    const char* regionPaths[] = {names[1].c_str(), names[2].c_str()};
    pyramid_elevation* e = nullptr;
    ASSERT_EQ(pyramid_elevation_open_regions(names[0].c_str(), regionPaths, 2, 4, 0, 3, &e), PYRAMID_OK);
    EXPECT_EQ(allElevations(e, 5), results[0]);
    pyramid_elevation_close(e);
    EXPECT_NE(results[0], results[1]); // two tile sizes
    for (int how = 1; how < 3; ++how) {
        EXPECT_EQ(results[static_cast<size_t>(2 * how)], results[0]) << how;
        EXPECT_EQ(results[static_cast<size_t>(2 * how + 1)], results[1]) << how;
    }
    for (const MemoryIo& i : io) {
        EXPECT_GT(i.reads.load(), 0);
        EXPECT_EQ(i.released.load(), 2); // two producers took each
    }
}

TEST(CApiSources, OrthoRegionSetsFromMemoryAndCallbacks) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = 8;
    h.channels = 3;
    auto solid = [](uint8_t base) {
        std::vector<uint8_t> p(12 * 12 * 3);
        for (size_t k = 0; k < p.size(); ++k) {
            p[k] = static_cast<uint8_t>(base + k % 7);
        }
        return p;
    };
    for (int file = 0; file < 2; ++file) {
        OrthoHeader fh = h;
        fh.rootLevel = file;
        fh.rootTx = file;
        OrthoFileWriter w(dir.file(file ? "region.dat" : "main.dat"), fh);
        for (int i = 0; i < 5; ++i) {
            const int l = i == 0 ? 0 : 1;
            w.writeTile(l, l ? (i - 1) % 2 : 0, l ? (i - 1) / 2 : 0, solid(static_cast<uint8_t>(10 * i + 100 * file)));
        }
        w.commit();
    }
    const std::vector<std::string> names = {dir.file("main.dat"), dir.file("region.dat")};
    const std::vector<uint8_t> bytes[] = {bytesOf(names[0]), bytesOf(names[1])};
    MemoryIo io[2];
    io[0].data = bytes[0];
    io[1].data = bytes[1];
    std::vector<std::vector<std::vector<uint8_t>>> results;
    for (int how = 0; how < 3; ++how) {
        std::vector<pyramid_source> sources;
        for (size_t k = 0; k < 2; ++k) {
            sources.push_back(how == 0 ? pathSource(names[k]) : how == 1 ? memorySource(bytes[k]) : ioSource(io[k], "o"));
        }
        const pyramid_source* regions[] = {&sources[1]};
        pyramid_ortho* o = nullptr;
        ASSERT_EQ(pyramid_ortho_open_sources(&sources[0], regions, 1, nullptr, &o), PYRAMID_OK) << pyramid_last_error();
        results.push_back(allOrtho(o, 3));
        pyramid_ortho_close(o);
    }
    // Tiles of the region (2, 3, 1), absent ones ((2, 0, 0)): both kinds are compared.
    EXPECT_EQ(results[0][5 + 3 + 4 * 1], solid(140));
    EXPECT_EQ(results[0][5 + 0].size(), 1u);
    EXPECT_EQ(results[1], results[0]);
    EXPECT_EQ(results[2], results[0]);
    EXPECT_EQ(io[0].released.load(), 1);
    EXPECT_EQ(io[1].released.load(), 1);
}

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
