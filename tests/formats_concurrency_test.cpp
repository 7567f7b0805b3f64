// Readers and writers used from several threads at once, and writers' determinism: the bytes
// of a file depend only on the order of the write() calls.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <thread>

#include "formats/error.hpp"
#include "formats/residual_file.hpp"
#include "formats/tile_table.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

constexpr int kThreads = 4;

struct TileId {
    int level, tx, ty;
};

std::vector<TileId> everyTile(const ResidualHeader& h) {
    std::vector<TileId> ids;
    for (int level = 0; level <= h.maxLevel; ++level) {
        const int side = static_cast<int>(h.tilesPerSide(level));
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                ids.push_back({level, tx, ty});
            }
        }
    }
    return ids;
}

// Every third tile is flat (all such tiles of a level share bytes); the others are distinct.
std::vector<int16_t> tileValues(const ResidualHeader& h, const TileId& t, size_t ordinal) {
    const int n = h.tileSamples(t.level);
    std::vector<int16_t> v(static_cast<size_t>(n) * n, static_cast<int16_t>(t.level));
    if (ordinal % 3 != 0) {
        for (size_t k = 0; k < v.size(); ++k) {
            v[k] = static_cast<int16_t>(k * 31 + ordinal * 1009);
        }
    }
    return v;
}

ResidualHeader smallHeader() {
    ResidualHeader h;
    h.minLevel = 1;
    h.maxLevel = 3; // 1 + 21 tiles
    h.tileSize = 8;
    return h;
}

TEST(ConcurrentWriter, TilesFromManyThreadsAllLandAndShare) {
    test::TempDir dir;
    const ResidualHeader h = smallHeader();
    const auto tiles = everyTile(h);
    const std::string path = dir.file("threads.dat");
    {
        ResidualFileWriter writer(path, h);
        std::atomic<size_t> next{0};
        std::vector<std::thread> threads;
        for (int k = 0; k < kThreads; ++k) {
            threads.emplace_back([&] {
                for (size_t i = next++; i < tiles.size(); i = next++) {
                    writer.writeTile(tiles[i].level, tiles[i].tx, tiles[i].ty, tileValues(h, tiles[i], i));
                }
            });
        }
        for (std::thread& t : threads) {
            t.join();
        }
        // Flat tiles of the same level are identical: all but the first of each level share.
        size_t flatTiles = 0;
        std::vector<bool> flatLevel(static_cast<size_t>(h.maxLevel) + 1, false);
        for (size_t i = 0; i < tiles.size(); i += 3) {
            ++flatTiles;
            flatLevel[static_cast<size_t>(tiles[i].level)] = true;
        }
        const auto levelsWithFlat = static_cast<size_t>(std::count(flatLevel.begin(), flatLevel.end(), true));
        EXPECT_EQ(writer.sharedTiles(), static_cast<int64_t>(flatTiles - levelsWithFlat));
        writer.commit();
    }
    auto reader = ResidualFileReader::open(path);
    for (size_t i = 0; i < tiles.size(); ++i) {
        EXPECT_EQ(reader->readTile(tiles[i].level, tiles[i].tx, tiles[i].ty), tileValues(h, tiles[i], i)) << i;
    }
}

TEST(WriterDeterminism, SameWriteOrderSameBytes) {
    test::TempDir dir;
    const ResidualHeader h = smallHeader();
    auto tiles = everyTile(h);
    std::reverse(tiles.begin(), tiles.end());
    std::string bytes[2];
    for (int run = 0; run < 2; ++run) {
        const std::string path = dir.file("run" + std::to_string(run) + ".dat");
        ResidualFileWriter writer(path, h);
        for (size_t i = 0; i < tiles.size(); ++i) {
            writer.writeTile(tiles[i].level, tiles[i].tx, tiles[i].ty, tileValues(h, tiles[i], i));
        }
        writer.commit();
        bytes[run] = test::readFile(path);
    }
    EXPECT_FALSE(bytes[0].empty());
    EXPECT_EQ(bytes[0], bytes[1]);
}

TEST(ConcurrentReader, ThreadsReadTheOriginalFileAsOneThreadDoes) {
    auto reader = ResidualFileReader::open(test::dataPath("proland/DEM.dat"));
    const auto tiles = everyTile(reader->header());
    std::vector<std::vector<int16_t>> serial;
    for (const TileId& t : tiles) {
        serial.push_back(reader->readTile(t.level, t.tx, t.ty));
    }
    std::atomic<int> mismatches{0};
    std::vector<std::thread> threads;
    for (int k = 0; k < kThreads; ++k) {
        threads.emplace_back([&, k] {
            // Each thread walks the tiles from a different start, twice, so reads overlap.
            for (size_t n = 0; n < 2 * tiles.size(); ++n) {
                const size_t i = (n + static_cast<size_t>(k) * 5) % tiles.size();
                if (reader->readTile(tiles[i].level, tiles[i].tx, tiles[i].ty) != serial[i]) {
                    ++mismatches;
                }
            }
        });
    }
    for (std::thread& t : threads) {
        t.join();
    }
    EXPECT_EQ(mismatches.load(), 0);
}

} // namespace
} // namespace pyramid
