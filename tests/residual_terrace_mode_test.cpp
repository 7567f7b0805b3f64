// Version 3's mode 5, the terrace mode (doc/format.md 1.8): a terraced tile's round trip with its
// parent plane (and its refusal without), pinned bytes, the blobs a decoder refuses (built with
// the format's own coder), the tiles it is tried on, and whole files of an 8-bit map's terraces:
// smaller, the same residuals, verified, the same bytes for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_context_values.hpp"
#include "formats/residual_file.hpp"
#include "formats/residual_range_coder.hpp"
#include "formats/residual_shadow.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/residual/residual_recode.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"
#include "tests/support/residual_tiles.hpp"

namespace pyramid {
namespace {

using context_coding::RangeEncoder;

// Terraces 39 apart (an 8-bit map of 10,000 m has steps of 39.2): the heights of a slope rising
// to the right and up, cut into steps, with the odd sample one off (rounding beside a step).
int32_t terraced(int x, int y) { return 39 * ((5 * x + 3 * y) / 11) + ((x * 7 + y * 3) % 13 == 0 ? 1 : 0); }

// A tile of `size` whose heights are terraced(), and its parent plane: a smooth slope through
// them, as an upsampled parent would be.
struct TerracedTile {
    int size;
    std::vector<int32_t> parent;
    std::vector<int16_t> residuals;
    explicit TerracedTile(int size_) : size(size_) {
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const int32_t plane = (39 * (5 * x + 3 * y)) / 11 - 19;
                parent.push_back(plane);
                residuals.push_back(static_cast<int16_t>(terraced(x, y) - plane));
            }
        }
    }
};

TEST(TerraceMode, ATerracedTileTakesTheModeRoundTripsAndIsRefusedWithoutItsPlane) {
    for (const int size : {33, 32}) {
        const TerracedTile t(size);
        const std::vector<uint8_t> chosen = encodeContextParentMode(t.residuals, size, t.parent);
        const std::vector<uint8_t> mode3 = encodeContextParentMode(t.residuals, size, t.parent, 3);
        ASSERT_GE(chosen.size(), 8u);
        EXPECT_EQ(chosen[6], 5) << size;
        EXPECT_EQ(chosen[7], 3);
        EXPECT_TRUE(contextBlobNeedsParent(chosen));
        EXPECT_LT(chosen.size() * 2, mode3.size()) << chosen.size() << " against " << mode3.size();
        EXPECT_EQ(decodeContextResiduals(chosen, size, "t", t.parent), t.residuals);
        EXPECT_EQ(encodeContextParentMode(t.residuals, size, t.parent, 5), chosen);
        test::expectContextBlobRefused(chosen, size, "DEM.dat: tile (4,3,2)", "without its parent tile");
    }
    // Forced on a tile that is not terraced (every integer of its range taken), it round trips too.
    const int size = 21;
    const std::vector<int16_t> noise = test::residualNoise(size, 300, 7);
    const std::vector<int32_t> flat(static_cast<size_t>(size * size), -5);
    const std::vector<uint8_t> forced = encodeContextParentMode(noise, size, flat, 5);
    EXPECT_EQ(forced[6], 5);
    EXPECT_EQ(decodeContextResiduals(forced, size, "t", flat), noise);
    EXPECT_NE(encodeContextParentMode(noise, size, flat)[6], 5); // not tried there
    // The extremes: shadows at the clamp's bounds beside full-range residuals.
    std::vector<int32_t> edges(static_cast<size_t>(size * size));
    std::vector<int16_t> wild(edges.size());
    for (size_t k = 0; k < edges.size(); ++k) {
        edges[k] = k % 3 == 0 ? 1 << 30 : -(1 << 30);
        wild[k] = static_cast<int16_t>(k % 2 == 0 ? 32767 : -32768);
    }
    EXPECT_EQ(decodeContextResiduals(encodeContextParentMode(wild, size, edges, 5), size, "t", edges), wild);
    // Four heights 2^31 apart (a range beyond isTerraced's bitmap): terraced, and chosen.
    const std::vector<uint8_t> chosenWild = encodeContextParentMode(wild, size, edges);
    EXPECT_EQ(chosenWild[6], 5);
    EXPECT_EQ(decodeContextResiduals(chosenWild, size, "t", edges), wild);
    EXPECT_THROW(encodeContextParentMode(noise, size, flat, 6), Error);
    // A parent plane beyond the format's +-2^30 has no mode-5 blob a decoder accepts.
    const std::vector<int32_t> beyond(static_cast<size_t>(size * size), (1 << 30) + 40000);
    EXPECT_THROW(encodeContextParentMode(noise, size, beyond, 5), Error);
}

TEST(TerraceMode, BytesOfAKnownTileArePinned) {
    const TerracedTile t(6);
    const std::vector<uint8_t> pinned = {0x50, 0x59, 0x52, 0x43, 0x06, 0x00, 0x05, 0x03, 0x00, 0x0e, 0x00, 0x10, 0x66, 0x71, 0xe0, 0xbb,
                                         0x9d, 0x33, 0x3f, 0x06, 0xf8, 0xa9, 0xc4, 0x4a, 0x78, 0x77, 0xad, 0x68, 0x1e, 0xc6, 0x00};
    EXPECT_EQ(encodeContextParentMode(t.residuals, 6, t.parent, 5), pinned);
    EXPECT_EQ(decodeContextResiduals(pinned, 6, "tile", t.parent), t.residuals);
}

// The format's numbers of the terrace list: the bit length in 6 equally likely bits, then the
// bits below the leading one, 16 at a time from the top.
void encodeNumber(RangeEncoder& coder, uint32_t u) {
    const int length = std::bit_width(u);
    coder.encodeBits(static_cast<uint32_t>(length), 6);
    for (int rest = length - 1; rest > 0;) {
        const int chunk = std::min(rest, 16);
        rest -= chunk;
        coder.encodeBits((u >> rest) & ((1u << chunk) - 1u), chunk);
    }
}

// A mode-5 blob of a tile of `size` whose list holds `count` terraces from `lowest` up, one apart,
// then the first sample's value `first` and, where that is 0, every other sample's 0 (a list of
// more terraces than the tile has samples is written without them).
std::vector<uint8_t> craftedBlob(int size, uint32_t count, int64_t lowest, int32_t first) {
    std::vector<uint8_t> out = {'P', 'Y', 'R', 'C', static_cast<uint8_t>(size), 0, 5, 3};
    RangeEncoder coder(out);
    encodeNumber(coder, count - 1);
    encodeNumber(coder, static_cast<uint32_t>(lowest >= 0 ? 2 * lowest : -2 * lowest - 1));
    if (count <= static_cast<uint32_t>(size * size)) {
        context_coding::Models<1> models;
        context_coding::Model<33> lengths;
        for (uint32_t k = 1; k < count; ++k) { // gaps of 0: bit length 0 from the adaptive table
            coder.encode(lengths.cumulative(0), lengths.count[0], lengths.total);
            lengths.update(0);
        }
        // (0, 0): table 0 of set 0; the sign model of pattern 4 and a prediction on the plane.
        context_coding::encodeValue(coder, models, 0, context_coding::signModel(4, 0, 0), first);
        for (int k = 1; first == 0 && k < size * size; ++k) { // then zeros: activity 0, the table by parity
            const int x = k % size, y = k / size;
            context_coding::encodeValue(coder, models, static_cast<size_t>((x & 1) + 2 * (y & 1)), 0, 0);
        }
    }
    coder.finish();
    return out;
}

void expectRefused(const std::vector<uint8_t>& blob, int size, const std::vector<int32_t>& plane, const std::string& mention) {
    try {
        decodeContextResiduals(blob, size, "DEM.dat: tile (3,1,1)", plane);
        ADD_FAILURE() << "accepted: " << mention;
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("DEM.dat: tile (3,1,1): ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    }
}

TEST(TerraceMode, BlobsTheEncoderCannotHaveWrittenAreRefused) {
    const std::vector<int32_t> plane(9, 100);
    // A blob made so is what the encoder writes for one terrace on the plane.
    const std::vector<int16_t> zeros(9, 0);
    EXPECT_EQ(craftedBlob(3, 1, 100, 0), encodeContextParentMode(zeros, 3, plane, 5));
    EXPECT_EQ(decodeContextResiduals(craftedBlob(3, 1, 100, 0), 3, "t", plane), zeros);
    expectRefused(craftedBlob(3, 10, 100, 0), 3, plane, "10 terraces in a tile of 3x3");
    expectRefused(craftedBlob(3, 2, 100, 2), 3, plane, "terrace 2 of 2");
    expectRefused(craftedBlob(3, 1, 100, -1), 3, plane, "terrace -1 of 1");
    expectRefused(craftedBlob(3, 1, (int64_t{1} << 30) + (1 << 15) + 1, 0), 3, plane, "a terrace beyond");
    expectRefused(craftedBlob(3, 1, 40000, 0), 3, plane, "a residual of 39900 is beyond int16");
}

// An 8-bit map's heights: syntheticHeights in steps of 10,000 / 255 m.
std::vector<float> eightBitHeights(int side) {
    std::vector<float> h = test::syntheticHeights(side, side, 2500.0f);
    for (float& v : h) {
        v = std::round(v * 255.0f / 10000.0f) * (10000.0f / 255.0f);
    }
    return h;
}

TEST(TerraceMode, TerracedFilesAreSmallerHoldTheSameResidualsAndVerify) {
    test::TempDir dir;
    const std::string input = dir.file("terraces.tif");
    test::writeFloatRaster(input, 193, 193, eightBitHeights(193));
    DemEncodeOptions o;
    o.tileSize = 48;
    o.rootTileSize = 12;
    o.scale = 1.0;
    encodeDem(input, dir.file("deflate.dat"), o);
    o.tiles.codec = ResidualCodec::Context;
    o.threads = 2;
    const DemReport context = encodeDem(input, dir.file("context.dat"), o);
    o.threads = 1;
    encodeDem(input, dir.file("context-1.dat"), o);
    EXPECT_EQ(test::bytesOf(dir.file("context.dat")), test::bytesOf(dir.file("context-1.dat")));
    EXPECT_TRUE(verifyDem(dir.file("context.dat"), input, DemVerifyOptions{}).ok());

    const auto deflate = ResidualFileReader::open(dir.file("deflate.dat"));
    const auto coded = ResidualFileReader::open(dir.file("context.dat"));
    const ResidualHeader& h = coded->header();
    int terraceTiles = 0;
    uint64_t stored = 0, asMode3 = 0;
    test::forEachTile(h, [&](int l, int tx, int ty) {
        const std::vector<int16_t> residuals = deflate->readTile(l, tx, ty);
        EXPECT_EQ(coded->readTile(l, tx, ty), residuals) << l << "," << tx << "," << ty;
        const std::vector<uint8_t> blob = coded->readTileBytes(l, tx, ty);
        if (contextBlobNeedsParent(blob) && blob[6] == 5) {
            ++terraceTiles;
            const std::vector<uint8_t> mode3 =
                encodeContextParentMode(residuals, h.tileSamples(l), coded->parentPlane(l, tx, ty), 3);
            EXPECT_LT(blob.size(), mode3.size()) << l << "," << tx << "," << ty;
            stored += blob.size();
            asMode3 += mode3.size();
        }
    });
    EXPECT_GT(terraceTiles, 8);
    EXPECT_LT(stored * 100, asMode3 * 80) << stored << " against " << asMode3;
    // Recoding gives the same bytes.
    ResidualRecodeOptions ro;
    ro.tiles.codec = ResidualCodec::Context;
    EXPECT_EQ(recodeResidualFile(dir.file("deflate.dat"), dir.file("recoded.dat"), ro).bytes, context.bytes);
}

} // namespace
} // namespace pyramid
