// The files written by the original Proland tools read back with the values they hold
// (cross-checked by decoding the TIFF strips independently with zlib).
#include <gtest/gtest.h>

#include <algorithm>

#include "formats/ortho_file.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_file.hpp"
#include "formats/tiff_tile.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

TEST(OriginalDemFile, HeaderAndLayout) {
    auto reader = ResidualFileReader::open(test::dataPath("proland/DEM.dat"));
    const ResidualHeader& h = reader->header();
    EXPECT_EQ(h.minLevel, 3);
    EXPECT_EQ(h.maxLevel, 5);
    EXPECT_EQ(h.tileSize, 192);
    EXPECT_EQ(h.rootLevel, 0);
    EXPECT_EQ(h.scale, 0.1f);
    EXPECT_EQ(h.tileCount(), 24);
    EXPECT_EQ(h.tileSamples(0), 29);
    EXPECT_EQ(h.tileSamples(1), 53);
    EXPECT_EQ(h.tileSamples(2), 101);
    EXPECT_EQ(h.tileSamples(5), 197);
    EXPECT_EQ(h.tileIndex(2, 0, 0), 2);
    EXPECT_EQ(h.tileIndex(3, 0, 0), 3);
    EXPECT_EQ(h.tileIndex(4, 1, 1), 7);
    EXPECT_EQ(h.tileIndex(5, 3, 3), 23);
    // Level 5 is stored in Z order: tile (5,2,0) follows (5,1,1) in the file.
    EXPECT_EQ(reader->table().range(h.tileIndex(5, 2, 0)).begin, 301560u - 0u);
    EXPECT_EQ(reader->table().range(h.tileIndex(5, 0, 1)).begin, 252170u);
}

TEST(OriginalDemFile, DecodesEveryTile) {
    auto reader = ResidualFileReader::open(test::dataPath("proland/DEM.dat"));
    const auto root = reader->readTile(0, 0, 0);
    ASSERT_EQ(root.size(), 29u * 29u);
    EXPECT_EQ(root[0], 1400);
    EXPECT_EQ(root[3], 1250);
    EXPECT_EQ(root[4], 1600);
    EXPECT_EQ(root[14 + 14 * 29], 1470);
    EXPECT_EQ(*std::min_element(root.begin(), root.end()), 830);
    EXPECT_EQ(*std::max_element(root.begin(), root.end()), 1920);
    const auto last = reader->readTile(5, 3, 3);
    EXPECT_EQ(*std::min_element(last.begin(), last.end()), -25);
    EXPECT_EQ(*std::max_element(last.begin(), last.end()), 19);
    int tiles = 0;
    for (int level = 0; level <= 5; ++level) {
        const int side = static_cast<int>(reader->header().tilesPerSide(level));
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                const auto tile = reader->readTile(level, tx, ty);
                const size_t s = static_cast<size_t>(reader->header().tileSamples(level));
                EXPECT_EQ(tile.size(), s * s);
                EXPECT_EQ(describeTiff(reader->readTileBytes(level, tx, ty)), "deflate-legacy");
                ++tiles;
            }
        }
    }
    EXPECT_EQ(tiles, 24);
}

// tests/data/context/dem-levels-0-2.dat is levels 0..2 of the original DEM.dat
// (tests/corpus/valid/dem-levels-0-2.dat) recoded once with context coding (doc/format.md 1.8)
// and committed: every later reader must decode it to the original's residuals.
TEST(OriginalDemFile, ContextCodedCopyDecodesToTheOriginalsResiduals) {
    auto original = ResidualFileReader::open(test::corpusPath("valid/dem-levels-0-2.dat"));
    auto context = ResidualFileReader::open(test::dataPath("context/dem-levels-0-2.dat"));
    ASSERT_EQ(context->header().maxLevel, original->header().maxLevel);
    ASSERT_EQ(context->header().tileSize, original->header().tileSize);
    for (int level = 0; level <= original->header().maxLevel; ++level) {
        EXPECT_EQ(describeResidualBlob(context->readTileBytes(level, 0, 0)), "context");
        EXPECT_EQ(context->readTile(level, 0, 0), original->readTile(level, 0, 0)) << level;
    }
    EXPECT_EQ(original->readTile(0, 0, 0)[0], 1400);
}

TEST(OriginalOrthoFile, HeaderAndTiles) {
    auto reader = OrthoFileReader::open(test::dataPath("proland/RGB.dat"));
    const OrthoHeader& h = reader->header();
    EXPECT_EQ(h.maxLevel, 1);
    EXPECT_EQ(h.tileSize, 192);
    EXPECT_EQ(h.channels, 4);
    EXPECT_EQ(h.flags, 0u);
    EXPECT_EQ(h.border(), 2); // flags bit 1 clear: bordered, as the original files are
    EXPECT_EQ(h.tilePixels(), 196);
    EXPECT_FALSE(h.dxt());
    EXPECT_EQ(h.tileCount(), 5);
    EXPECT_EQ(reader->table().range(0).size(), 38188u);
    for (int i = 0; i < 5; ++i) {
        const int level = i == 0 ? 0 : 1;
        const int tx = i == 0 ? 0 : (i - 1) % 2;
        const int ty = i == 0 ? 0 : (i - 1) / 2;
        const auto tile = reader->readTile(level, tx, ty);
        EXPECT_EQ(tile.size(), 196u * 196u * 4u);
    }
}

} // namespace
} // namespace pyramid
