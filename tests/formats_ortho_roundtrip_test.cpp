// Writer -> reader round trips for ortho files (tests/support/pyramid_tiles.hpp): every tile
// encoding, every channel count, with and without borders, and a region root's coordinates.
//
// Tolerances (smooth gradients, the only content where they are meaningful):
//   JPEG quality 95: max abs difference <= 8 per sample (1 measured).
//   DXT1 / DXT5, cluster fit: max abs difference <= 8 per sample, alpha included (RGB565
//   endpoints and 4-level interpolation; 5 measured on these 3-levels-a-pixel gradients).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/tiff_tile.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/pyramid_tiles.hpp"

namespace pyramid {
namespace {

using test::orthoTiles;
using test::smoothPixels;
using test::TileId;

int maxAbsDiff(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    EXPECT_EQ(a.size(), b.size());
    int worst = 0;
    for (size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
        worst = std::max(worst, std::abs(int(a[k]) - int(b[k])));
    }
    return worst;
}

struct OrthoCase {
    int channels;
    uint32_t flags;
    TiffCompression compression;
    int tolerance; // 0 = exact
};

void orthoRoundTrip(const OrthoCase& c) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 2;
    h.tileSize = 16;
    h.channels = (c.flags & OrthoHeader::kFlagDxt) ? std::max(3, c.channels) : c.channels;
    h.flags = c.flags;
    const std::string path = dir.file("ortho.dat");
    OrthoTileEncoding encoding;
    encoding.compression = c.compression;
    encoding.jpegQuality = 95;
    const int size = h.tilePixels();
    const auto tiles = orthoTiles(h, 3);
    {
        OrthoFileWriter writer(path, h);
        for (const TileId& t : tiles) {
            writer.writeTile(t.level, t.tx, t.ty, smoothPixels(size, c.channels, t), encoding);
        }
        writer.commit();
    }
    auto reader = OrthoFileReader::open(path);
    EXPECT_EQ(reader->header().flags, c.flags);
    EXPECT_EQ(reader->header().channels, h.channels);
    EXPECT_EQ(reader->header().tilePixels(), (c.flags & OrthoHeader::kFlagNoBorder) ? 16 : 20);
    int worst = 0;
    for (const TileId& t : tiles) {
        const auto got = reader->readTile(t.level, t.tx, t.ty);
        auto want = smoothPixels(size, c.channels, t);
        if (h.dxt() && c.channels < 3) {
            // DXT1 tiles decode to RGB; grey sources are replicated.
            const auto grey = smoothPixels(size, 1, t);
            want.clear();
            for (uint8_t g : grey) {
                want.insert(want.end(), {g, g, g});
            }
        }
        if (c.tolerance == 0) {
            EXPECT_EQ(got, want) << t.level << "," << t.tx << "," << t.ty;
        }
        worst = std::max(worst, maxAbsDiff(got, want));
    }
    EXPECT_LE(worst, c.tolerance);
    if (c.tolerance > 0) {
        EXPECT_GT(worst, 0) << "a lossy codec that is exact: is it really used?";
    }
}

TEST(OrthoRoundTrip, LosslessTiffEveryChannelCountWithAndWithoutBorders) {
    for (TiffCompression compression : {TiffCompression::Deflate, TiffCompression::Lzw, TiffCompression::None}) {
        for (int channels = 1; channels <= 4; ++channels) {
            for (uint32_t flags : {0u, OrthoHeader::kFlagNoBorder}) {
                SCOPED_TRACE(testing::Message() << "compression " << int(compression) << " channels " << channels
                                                << " flags " << flags);
                orthoRoundTrip({channels, flags, compression, 0});
            }
        }
    }
}

TEST(OrthoRoundTrip, JpegWithinEightAtQuality95) {
    for (int channels : {1, 3}) {
        for (uint32_t flags : {0u, OrthoHeader::kFlagNoBorder}) {
            SCOPED_TRACE(testing::Message() << "channels " << channels << " flags " << flags);
            orthoRoundTrip({channels, flags, TiffCompression::Jpeg, 8});
        }
    }
}

TEST(OrthoRoundTrip, JpegRefusesTwoAndFourChannels) {
    for (int channels : {2, 4}) {
        EXPECT_THROW(encodeTiff8(smoothPixels(8, channels, {0, 0, 0}), 8, 8, channels, TiffCompression::Jpeg), Error);
    }
}

TEST(OrthoRoundTrip, DxtWithinEight) {
    for (int channels = 1; channels <= 4; ++channels) {
        for (uint32_t flags : {OrthoHeader::kFlagDxt, OrthoHeader::kFlagDxt | OrthoHeader::kFlagNoBorder}) {
            SCOPED_TRACE(testing::Message() << "channels " << channels << " flags " << flags);
            orthoRoundTrip({channels, flags, TiffCompression::Deflate, 8});
        }
    }
}

TEST(OrthoRoundTrip, DxtBlobsHaveTheBlockSize) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 0;
    h.tileSize = 12; // 16 pixels with borders: 4 x 4 blocks
    for (int channels : {3, 4}) {
        h.channels = channels;
        h.flags = OrthoHeader::kFlagDxt;
        const std::string path = dir.file("dxt" + std::to_string(channels) + ".dat");
        {
            OrthoFileWriter writer(path, h);
            writer.writeTile(0, 0, 0, smoothPixels(16, channels, {0, 0, 0}));
            writer.commit();
        }
        const auto blob = OrthoFileReader::open(path)->readTileBytes(0, 0, 0);
        EXPECT_EQ(blob.size(), 16u * (channels == 4 ? 16u : 8u)); // DXT5 16 bytes a block, DXT1 8
    }
}

TEST(OrthoRoundTrip, RegionRootKeepsItsCoordinates) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = 8;
    h.channels = 3;
    h.rootLevel = 4;
    h.rootTx = 9;
    h.rootTy = 15;
    const std::string path = dir.file("region.dat");
    {
        OrthoFileWriter writer(path, h);
        for (const TileId& t : orthoTiles(h, 4)) {
            writer.writeTile(t.level, t.tx, t.ty, smoothPixels(h.tilePixels(), 3, t));
        }
        writer.commit();
    }
    auto reader = OrthoFileReader::open(path);
    EXPECT_EQ(reader->header().rootLevel, 4);
    EXPECT_EQ(reader->header().rootTx, 9);
    EXPECT_EQ(reader->header().rootTy, 15);
    EXPECT_EQ(reader->readTile(1, 0, 1), smoothPixels(h.tilePixels(), 3, {1, 0, 1}));
}

} // namespace
} // namespace pyramid
