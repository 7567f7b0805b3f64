// The C API's other opens: memory and I/O callbacks give what paths give, on the original tools'
// files and on region sets (residual and ortho).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "formats/ortho_file.hpp"
#include "libpyramid/capi/pyramid.h"
#include "tests/support/c_api_sources.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using test::bytesOf;
using test::ioSource;
using test::memorySource;
using test::MemoryIo;
using test::pathSource;
using test::writeResidualSet;

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

} // namespace
} // namespace pyramid
