// Version 2 of the context-coded residual tile (doc/format.md, 1.8): round trips on the tiles of
// a coast's pyramid and on adversarial tiles, the longest escapes, pinned bytes of versions 1 and
// 2, and the refusal of damaged blobs. residual_codec_test.cpp has the tests every version shares.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/residual_tiles.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

std::vector<int16_t> noise(int size, int spread, uint32_t seed) { return test::residualNoise(size, spread, seed); }

// A cliff along a wavy line: 0 on one side, the ringing of the upsampling (+-75 beside the
// line, +-600 on it) and small residuals on the other, as flooded coasts give.
std::vector<int16_t> cliff(int size) {
    std::vector<int16_t> v(static_cast<size_t>(size) * static_cast<size_t>(size), 0);
    std::mt19937 rng(9);
    std::uniform_int_distribution<int> d(-3, 3);
    for (int y = 0; y < size; ++y) {
        const int edge = size / 2 + static_cast<int>(6.0 * std::sin(0.2 * y));
        for (int x = 0; x < size; ++x) {
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
            if (x == edge) {
                v[i] = static_cast<int16_t>(y % 2 == 0 ? 600 + d(rng) : -590 + d(rng));
            } else if (x == edge - 1 || x == edge + 1) {
                v[i] = static_cast<int16_t>(x % 2 == 1 ? 75 : -75);
            } else if (x > edge) {
                v[i] = static_cast<int16_t>(d(rng));
            }
        }
    }
    return v;
}

std::vector<int16_t> decoded(const std::vector<uint8_t>& blob, int size) { return decodeContextResiduals(blob, size, "tile"); }

TEST(ContextResidualsV2, EveryModeRoundTripsAdversarialTiles) {
    for (const int size : {1, 2, 3, 5, 29, 160}) {
        std::vector<std::vector<int16_t>> tiles = {noise(size, 2, 1), noise(size, 40, 2), noise(size, 32767, 3),
                                                   cliff(size), std::vector<int16_t>(static_cast<size_t>(size * size), 0)};
        std::vector<int16_t> extremes(static_cast<size_t>(size * size));
        for (size_t k = 0; k < extremes.size(); ++k) {
            extremes[k] = (k + k / static_cast<size_t>(size)) % 2 == 0 ? int16_t{-32768} : int16_t{32767};
        }
        tiles.push_back(extremes);
        tiles.push_back(std::vector<int16_t>(static_cast<size_t>(size * size), int16_t{-32768}));
        for (size_t t = 0; t < tiles.size(); ++t) {
            for (int mode = 0; mode < 3; ++mode) {
                const std::vector<uint8_t> blob = encodeContextResiduals(tiles[t], size, 2, mode);
                ASSERT_EQ(blob[6], mode);
                ASSERT_EQ(blob[7], 2);
                EXPECT_EQ(decoded(blob, size), tiles[t]) << size << " tile " << t << " mode " << mode;
            }
            const std::vector<uint8_t> best = encodeContextResiduals(tiles[t], size);
            EXPECT_EQ(best[7], 2); // the version the encoder writes
            EXPECT_EQ(decoded(best, size), tiles[t]) << size << " tile " << t;
        }
    }
}

// Mode 2's largest values, 79871 either way: a sample of odd column and row whose W and S
// neighbours are at one int16 limit and WW and SS at the other, predicted as -47104 (or 47103)
// and holding the other limit. Their escapes have the longest bit length (k = 16).
TEST(ContextResidualsV2, TheLongestEscapesRoundTrip) {
    for (const int sign : {1, -1}) {
        const auto low = static_cast<int16_t>(sign > 0 ? -32768 : 32767);
        const auto high = static_cast<int16_t>(sign > 0 ? 32767 : -32768);
        std::vector<int16_t> tile(9 * 9, 0);
        tile[3 * 9 + 2] = low;  // W of (3, 3)
        tile[2 * 9 + 3] = low;  // S
        tile[3 * 9 + 1] = high; // WW
        tile[1 * 9 + 3] = high; // SS
        tile[3 * 9 + 3] = high;
        for (int mode = 0; mode < 3; ++mode) {
            EXPECT_EQ(decoded(encodeContextResiduals(tile, 9, 2, mode), 9), tile) << sign << " " << mode;
        }
    }
}

// The format's bytes, pinned: a change of version 2's coder or constants fails here before it
// reaches a file, and version 1's blobs (files of 2026-12-03 on) decode as they were written.
TEST(ContextResidualsV2, BytesOfKnownTilesArePinned) {
    const std::vector<int16_t> grid = {0, 3, 0, -2, 0, 4, 6, 1, -5, 2, 0, 2, 0, 1, 0, -3, -4, 2, 7, 1, 0, -1, 0, 300, 0};
    const std::vector<uint8_t> version1 = {0x50, 0x59, 0x52, 0x43, 0x05, 0x00, 0x02, 0x01, 0x00, 0x4d, 0xe4, 0x3f,
                                           0xde, 0x30, 0x67, 0x74, 0xd7, 0xa7, 0x76, 0xe0, 0xfd, 0x7d, 0x80, 0x00};
    EXPECT_EQ(decoded(version1, 5), grid);
    EXPECT_EQ(encodeContextResiduals(grid, 5, 1, 2), version1);
    const std::vector<uint8_t> version2 = {
        0x50, 0x59, 0x52, 0x43, 0x05, 0x00, 0x02, 0x02, 0x00, 0x4c, 0x08, 0xb8,
        0x5a, 0xe5, 0xb8, 0x6a, 0xb0, 0x6c, 0xa9, 0xe6, 0x9f, 0xb7, 0x00, 0x00};
    EXPECT_EQ(encodeContextResiduals(grid, 5, 2, 2), version2);
    EXPECT_EQ(decoded(version2, 5), grid);

    // A version-1 tile with escapes of every length up to 2^10, in mode 0.
    std::vector<int16_t> escapes(7 * 7);
    for (size_t k = 0; k < escapes.size(); ++k) {
        escapes[k] = static_cast<int16_t>((k % 2 == 0 ? 1 : -1) * ((1 << (k % 11)) + static_cast<int>(k)));
    }
    const std::vector<uint8_t> escapes1 = {
        0x50, 0x59, 0x52, 0x43, 0x07, 0x00, 0x00, 0x01, 0x00, 0x88, 0xaa, 0x82,
        0xa0, 0x18, 0x2c, 0x07, 0x55, 0xea, 0x9a, 0x41, 0xae, 0x3d, 0x38, 0xcc,
        0xf2, 0x96, 0xc3, 0x2d, 0xa6, 0x44, 0xf5, 0x75, 0x6d, 0xda, 0x15, 0xe9,
        0x8a, 0xcd, 0x35, 0x78, 0x15, 0xc8, 0xeb, 0xf7, 0x1f, 0x13, 0x0b, 0xba,
        0x45, 0x2e, 0xcf, 0x2d, 0x40, 0x94, 0xea, 0x14, 0xb4, 0xb9, 0x11, 0x95,
        0xdb, 0xbf, 0xd1, 0x6a, 0x02, 0x50, 0xce, 0x9d, 0x6a, 0x1a, 0xd7, 0xa5,
        0x54, 0xdd, 0x14, 0x6e, 0xe0, 0x8a, 0x98, 0x8f, 0xb8, 0x45, 0x25, 0xac,
        0xc9, 0x08, 0xef, 0x5a, 0x67, 0xb9, 0x35, 0x97, 0xd3, 0xde, 0xbb, 0xd6,
        0xdd, 0x94, 0x00};
    EXPECT_EQ(decoded(escapes1, 7), escapes);
    EXPECT_EQ(encodeContextResiduals(escapes, 7, 1, 0), escapes1);
    const std::vector<uint8_t> escapes2 = {
        0x50, 0x59, 0x52, 0x43, 0x07, 0x00, 0x00, 0x02, 0x00, 0x84, 0xe7, 0x08,
        0x07, 0x4a, 0xc3, 0x7b, 0x4a, 0xd3, 0x13, 0x26, 0x5b, 0xea, 0x2e, 0xd2,
        0x30, 0x49, 0x99, 0x02, 0xa5, 0x5b, 0xdc, 0xec, 0x64, 0xf8, 0xdb, 0x89,
        0xb5, 0xa2, 0xfa, 0xa5, 0x71, 0x35, 0x7c, 0x08, 0x70, 0x29, 0x31, 0xff,
        0x27, 0x5e, 0xc2, 0x11, 0xc7, 0x4e, 0xfa, 0x90, 0x3b, 0x83, 0x35, 0xdc,
        0x3e, 0xdc, 0x75, 0xa4, 0xb8, 0x5a, 0x9a, 0x18, 0xf3, 0x7a, 0x0a, 0x29,
        0xd5, 0x49, 0x2d, 0x29, 0x9b, 0xf6, 0x42, 0x9b, 0x93, 0xb3, 0x5a, 0x2d,
        0x5e, 0xef, 0x02, 0x2f, 0x5c, 0x35, 0x7f, 0x75, 0x30, 0xd9, 0x82};
    EXPECT_EQ(encodeContextResiduals(escapes, 7, 2, 0), escapes2);
    EXPECT_EQ(decoded(escapes2, 7), escapes);
}

TEST(ContextResidualsV2, DamagedBlobsAreRefused) {
    const std::vector<int16_t> tile = cliff(29);
    const std::vector<uint8_t> blob = encodeContextResiduals(tile, 29, 2, 2);
    const auto refused = [](const std::vector<uint8_t>& b, int size, const std::string& mention) {
        test::expectContextBlobRefused(b, size, "DEM.dat: tile (3,0,1)", mention);
    };
    for (size_t cut = 0; cut < blob.size(); ++cut) {
        refused(std::vector<uint8_t>(blob.begin(), blob.begin() + static_cast<std::ptrdiff_t>(cut)), 29, "");
    }
    std::vector<uint8_t> longer = blob;
    longer.push_back(0);
    refused(longer, 29, "1 bytes after the end");
    std::vector<uint8_t> mode = blob;
    mode[6] = 3;
    refused(mode, 29, "unknown kind (mode 3, version 2)");
    std::vector<uint8_t> version = blob;
    version[7] = 3;
    refused(version, 29, "unknown kind (mode 2, version 3)");
    refused(blob, 28, "29 samples a side, expected 28");
    // Read as version 1 (or 1's as 2), the stream means other values: an error, or other residuals.
    std::vector<uint8_t> other = blob;
    other[7] = 1;
    try {
        EXPECT_NE(decodeContextResiduals(other, 29, "t"), tile);
    } catch (const Error&) {
    }
    // Any byte changed: an error or other residuals, never a crash (the fuzz target goes further).
    for (size_t k = 8; k < blob.size(); ++k) {
        std::vector<uint8_t> flipped = blob;
        flipped[k] ^= 0xa5;
        try {
            EXPECT_EQ(decodeContextResiduals(flipped, 29, "t").size(), tile.size());
        } catch (const Error&) {
        }
    }
}

// The tiles of a coast's pyramid (terrain above 1200 m lowered to the shore, a flat sea below):
// files in version 2 (and the parent mode's version 3, tests/residual_parent_mode_test.cpp) hold
// the Deflate file's residuals, pass verification, and their tiles are smaller in version 2 than
// in version 1.
TEST(ContextResidualsV2, ACoastsTilesRoundTripAndShrink) {
    test::TempDir dir;
    const std::string input = dir.file("coast.tif");
    std::vector<float> heights = test::syntheticHeights(193, 193, 2500.0f);
    for (float& h : heights) {
        h = std::max(std::round(h) - 1200.0f, 0.0f);
    }
    test::writeFloatRaster(input, 193, 193, heights);
    DemEncodeOptions o;
    o.tileSize = 48;
    o.rootTileSize = 12;
    o.scale = 1.0;
    for (const auto codec : {ResidualCodec::Deflate, ResidualCodec::Context}) {
        o.tiles.codec = codec;
        encodeDem(input, dir.file(std::string(residualCodecName(codec)) + ".dat"), o);
    }
    EXPECT_TRUE(verifyDem(dir.file("context.dat"), input, DemVerifyOptions{}).ok());
    const auto deflate = ResidualFileReader::open(dir.file("deflate.dat"));
    const auto context = ResidualFileReader::open(dir.file("context.dat"));
    const ResidualHeader& h = deflate->header();
    size_t bytes1 = 0, bytes2 = 0;
    int versions2 = 0, tiles = 0;
    for (int l = 0; l <= h.maxLevel; ++l) {
        const int size = h.tileSamples(l);
        for (int ty = 0; ty < h.tilesPerSide(l); ++ty) {
            for (int tx = 0; tx < h.tilesPerSide(l); ++tx) {
                const std::vector<int16_t> residuals = deflate->readTile(l, tx, ty);
                ASSERT_EQ(context->readTile(l, tx, ty), residuals) << l << "," << tx << "," << ty;
                const std::vector<uint8_t> stored = context->readTileBytes(l, tx, ty);
                versions2 += stored.size() > 7 && (stored[7] == 2 || stored[7] == 3) ? 1 : 0;
                ++tiles;
                bytes1 += encodeContextResiduals(residuals, size, 1).size();
                bytes2 += encodeContextResiduals(residuals, size, 2).size();
            }
        }
    }
    EXPECT_EQ(versions2, tiles);
    EXPECT_LT(bytes2, bytes1);
}

} // namespace
} // namespace pyramid
