// Version 3 of the context-coded tile, the parent modes (doc/format.md 1.8): the shadows' integer
// upsampling, a tile's round trip with its parent plane (and its refusal without) in modes 3 and
// 4, pinned bytes of each, and whole files: smaller on a coast and behind cliffs (mode 4), the
// same residuals, the same heights through sets and runtime tiles of another size, the same
// bytes for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_file.hpp"
#include "formats/residual_shadow.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/residual/residual_recode.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/runtime/residual_producer.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"
#include "tests/support/residual_tiles.hpp"

namespace pyramid {
namespace {

std::vector<int32_t> plane(int size, int32_t (*f)(int, int)) {
    std::vector<int32_t> p(static_cast<size_t>(size) * static_cast<size_t>(size));
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            p[static_cast<size_t>(y * size + x)] = f(x, y);
        }
    }
    return p;
}

// A thread keeps the planes of its last tile for the next one of that size (residual_context_state.hpp,
// PlanesLease): a tile's bytes and residuals must not depend on the tiles the thread coded before,
// nor on a blob refused half-way. Each kind of tile is coded after other tiles of every kind and
// after a refused blob, and compared with its coding on a thread of its own.
TEST(ParentMode, TilesDoNotDependOnTheTilesCodedBeforeThemOnTheirThread) {
    const int size = 37;
    const std::vector<int32_t> parent = plane(size, [](int x, int y) { return 7 * x - 3 * y + ((x * y) % 11) * 40; });
    const std::vector<int32_t> other = plane(size, [](int x, int y) { return -900 * x + 5 * y; });
    const std::vector<int16_t> tile = test::residualNoise(size, 30, 7);
    const std::vector<int16_t> loud = test::residualNoise(size, 32767, 8);
    // The kinds: version 2's modes 0 to 2 (-1..-3 here), the parent modes 3, 4 and 5.
    const auto encode = [&](const std::vector<int16_t>& r, const std::vector<int32_t>& p, int kind) {
        return kind < 0 ? encodeContextResiduals(r, size, 2, -kind - 1) : encodeContextParentMode(r, size, p, kind);
    };
    const std::vector<int> kinds = {-1, -2, -3, 3, 4, 5};
    for (const int kind : kinds) {
        std::vector<uint8_t> alone;
        std::vector<int16_t> decodedAlone;
        std::string error;
        std::thread([&] {
            try {
                alone = encode(tile, parent, kind);
                decodedAlone = decodeContextResiduals(alone, size, "t", parent);
            } catch (const Error& e) {
                error = e.what();
            }
        }).join();
        ASSERT_EQ(error, "") << "kind " << kind;
        ASSERT_EQ(decodedAlone, tile) << "kind " << kind;
        for (const int before : kinds) {
            const std::vector<uint8_t> blob = encode(loud, other, before);
            ASSERT_EQ(decodeContextResiduals(blob, size, "t", other), loud);
            std::vector<uint8_t> cut(blob.begin(), blob.begin() + static_cast<std::ptrdiff_t>(blob.size() / 2));
            cut.resize(blob.size(), 0xff);
            try {
                (void)decodeContextResiduals(cut, size, "t", other);
            } catch (const Error&) {
            }
            EXPECT_EQ(encode(tile, parent, kind), alone) << "kind " << kind << " after " << before;
            EXPECT_EQ(decodeContextResiduals(alone, size, "t", parent), tile) << "kind " << kind << " after " << before;
        }
    }
}

TEST(ParentMode, ShadowsAreUpsampledInIntegersAndPlacedAsTheirParents) {
    // A plane is reproduced exactly: even samples copy the parent, odd ones are midpoints.
    const std::vector<int32_t> parent = plane(9, [](int x, int y) { return 16 * x - 32 * y + 5; });
    const std::vector<int32_t> child = upsampleShadow(parent, 9, 9, 1, 1);
    for (int j = 0; j < 9; ++j) {
        for (int i = 0; i < 9; ++i) {
            EXPECT_EQ(child[static_cast<size_t>(j * 9 + i)], 8 * (i + 2) - 16 * (j + 2) + 5) << i << "," << j;
        }
    }
    // A step: the filter's overshoot, (9 * 0 + 9 * 160 - 0 - 160 + 8) >> 4 = 80 at the midpoint.
    const std::vector<int32_t> step = plane(9, [](int x, int) { return x >= 4 ? 160 : 0; });
    const std::vector<int32_t> up = upsampleShadow(step, 9, 9, 1, 1);
    EXPECT_EQ(up[5], 80);  // between parent columns 3 and 4
    EXPECT_EQ(up[3], -10); // beside it: (9 * 0 - 160 + 8) >> 4
    EXPECT_EQ(up[4], 0);
    // Below minLevel + 1 a tile's parent is the whole tile above; deeper, its quadrant.
    ResidualHeader h;
    h.minLevel = 2;
    h.maxLevel = 4;
    h.tileSize = 16;
    const ShadowParent whole = shadowParentOf(h, 2, 0, 0);
    EXPECT_EQ(std::tie(whole.level, whole.tx, whole.ty, whole.px, whole.py), std::tuple(1, 0, 0, 1, 1));
    const ShadowParent quadrant = shadowParentOf(h, 4, 3, 2);
    EXPECT_EQ(std::tie(quadrant.level, quadrant.tx, quadrant.ty, quadrant.px, quadrant.py), std::tuple(3, 1, 1, 9, 1));
    const std::vector<int16_t> r = {1, -2, 3, 32767};
    EXPECT_EQ(shadowOf(std::vector<int32_t>{10, 20, 30, 1 << 30}, r), (std::vector<int32_t>{11, 18, 33, 1 << 30}));
}

TEST(ParentMode, ATileRoundTripsWithItsPlaneAndIsRefusedWithout) {
    const int size = 21;
    const std::vector<int16_t> residuals = test::residualNoise(size, 40, 3);
    const std::vector<int32_t> parent = plane(size, [](int x, int y) { return 300 * x - 170 * y + (x * y) % 7; });
    const std::vector<uint8_t> blob = encodeContextParentMode(residuals, size, parent);
    ASSERT_GE(blob.size(), 8u);
    EXPECT_EQ(blob[6], 3);
    EXPECT_EQ(blob[7], 3);
    EXPECT_TRUE(contextBlobNeedsParent(blob));
    EXPECT_FALSE(contextBlobNeedsParent(encodeContextResiduals(residuals, size)));
    EXPECT_EQ(decodeContextResiduals(blob, size, "t", parent), residuals);
    EXPECT_EQ(decodeResidualBlob(blob, size, "t", parent), residuals);
    test::expectContextBlobRefused(blob, size, "DEM.dat: tile (2,1,0)", "without its parent tile");
    // The extremes: shadows at the clamp's bounds beside full-range residuals.
    const std::vector<int16_t> wild = test::residualNoise(size, 32767, 5);
    const std::vector<int32_t> edges = plane(size, [](int x, int y) { return ((x ^ y) & 1) != 0 ? 1 << 30 : -(1 << 30); });
    EXPECT_EQ(decodeContextResiduals(encodeContextParentMode(wild, size, edges), size, "t", edges), wild);
    // Another version-3 mode, or mode 3 in version 2, is not a blob the encoder writes.
    std::vector<uint8_t> other = blob;
    other[6] = 2;
    EXPECT_THROW(decodeContextResiduals(other, size, "t", parent), Error);
    other = blob;
    other[7] = 2;
    EXPECT_THROW(decodeContextResiduals(other, size, "t", parent), Error);
    other = blob;
    other[7] = 4;
    EXPECT_THROW(decodeContextResiduals(other, size, "t", parent), Error);
    other = blob;
    other[6] = 6;
    EXPECT_THROW(decodeContextResiduals(other, size, "t", parent), Error);
    EXPECT_THROW(encodeContextParentMode(residuals, size, parent, 2), Error);
    // Mode 4 (steps) is only tried where the tile has a shore's step; forced, it round trips
    // without one too, and at the extremes.
    const std::vector<uint8_t> steps = encodeContextParentMode(residuals, size, parent, 4);
    EXPECT_EQ(steps[6], 4);
    EXPECT_EQ(decodeContextResiduals(steps, size, "t", parent), residuals);
    test::expectContextBlobRefused(steps, size, "DEM.dat: tile (2,1,0)", "without its parent tile");
    EXPECT_EQ(decodeContextResiduals(encodeContextParentMode(wild, size, edges, 4), size, "t", edges), wild);
}

// A coast: the parent holds land beside a flat sea at 0, along a ragged shore; the child's sea
// samples hold exactly the residuals that bring the upsampled parent's ringing back to 0.
// Predicted from the shadows, the ringing costs less than version 2, which sees only residuals,
// makes it cost (the file of the test below saves more: real shores ring at every level).
bool sea(int x, int y) { return x < 10 + (y * 7) % 5; }

TEST(ParentMode, TheShoresRingingCostsLessThanInVersion2) {
    const int size = 37;
    const std::vector<int32_t> parent = plane(size, [](int x, int y) { return sea(x, y) ? 0 : 900 + 40 * y - 25 * x; });
    const std::vector<int32_t> up = upsampleShadow(parent, size, size, 1, 1);
    std::vector<int16_t> residuals = test::residualNoise(size, 1, 9);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = static_cast<size_t>(y * size + x);
            if (sea(x / 2 + 1, y / 2 + 1)) { // heights 0
                residuals[i] = static_cast<int16_t>(-up[i]);
            }
        }
    }
    const size_t parentMode = encodeContextParentMode(residuals, size, up).size();
    const size_t version2 = encodeContextResiduals(residuals, size).size();
    EXPECT_LT(parentMode, version2);
    EXPECT_EQ(decodeContextResiduals(encodeContextParentMode(residuals, size, up), size, "t", up), residuals);
}

// A sea behind cliffs: the parent holds land of 1200 m and more beside a sea at 0. The child's
// heights are 0 in the sea and the land's plane beside it (plus noise): its residuals bring the
// upsampled parent's ringing back to both, on either side of the cliff. Mode 4 codes on which
// side of each step a sample lies, and each side from its own neighbours.
bool cliffSea(int x, int y) { return x < 9 + (y * 5) % 4; }
int32_t cliffLand(int x, int y) { return 1200 + 30 * y + 20 * x; }

// The residuals of a child placed at (1, 1) of `parent`, whose sea is where the parent is 0.
std::vector<int16_t> cliffResiduals(int size, const std::vector<int32_t>& parent, const std::vector<int32_t>& up) {
    std::vector<int16_t> residuals = test::residualNoise(size, 2, 11);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t i = static_cast<size_t>(y * size + x);
            const bool sea = parent[static_cast<size_t>((y / 2 + 1) * size + x / 2 + 1)] == 0;
            const int32_t height = sea ? 0 : (2 * cliffLand(0, 0) + 30 * (y + 2) + 20 * (x + 2)) / 2 + residuals[i];
            residuals[i] = static_cast<int16_t>(height - up[i]);
        }
    }
    return residuals;
}

TEST(ParentMode, CliffsTakeTheStepModeAndRoundTrip) {
    for (const int size : {37, 36}) { // an even size: the clamped plane's last odd column and row
        const std::vector<int32_t> parent = plane(size, [](int x, int y) { return cliffSea(x, y) ? 0 : cliffLand(x, y); });
        const std::vector<int32_t> up = upsampleShadow(parent, size, size, 1, 1);
        const std::vector<int16_t> residuals = cliffResiduals(size, parent, up);
        const std::vector<uint8_t> chosen = encodeContextParentMode(residuals, size, up);
        const std::vector<uint8_t> mode3 = encodeContextParentMode(residuals, size, up, 3);
        EXPECT_EQ(chosen[6], 4) << size;
        EXPECT_EQ(mode3[6], 3);
        EXPECT_LT(chosen.size(), mode3.size()) << size;
        EXPECT_EQ(decodeContextResiduals(chosen, size, "t", up), residuals);
        EXPECT_EQ(decodeContextResiduals(mode3, size, "t", up), residuals);
    }
}

TEST(ParentMode, BytesOfAKnownTileArePinned) {
    const std::vector<int16_t> tile = {0, 1, -1, 2, 0, 3, -4, 0, 0, 1, 0, 0, 7, -2, 0, 1, 1, 0, 0, 0, -9, 2, 0, 0, 4};
    const std::vector<int32_t> parent = {0, 0, 5, 9, 12, 0, 0, 5, 9, 12, 0, 1, 6, 9, 13, 0, 1, 6, 10, 13, 0, 1, 6, 10, 14};
    const std::vector<uint8_t> pinned = {0x50, 0x59, 0x52, 0x43, 0x05, 0x00, 0x03, 0x03, 0x00, 0x42, 0x11, 0xc9,
                                         0x4a, 0x7b, 0x91, 0xa4, 0xc9, 0x4b, 0x21, 0x77, 0x19, 0x43, 0x5c, 0x00};
    EXPECT_EQ(encodeContextParentMode(tile, 5, parent), pinned);
    EXPECT_EQ(decodeContextResiduals(pinned, 5, "tile", parent), tile);
    // Mode 4: a 7 x 7 tile behind a cliff (whose few heights take mode 5, the terraces, where
    // the encoder chooses: tests/residual_terrace_mode_test.cpp).
    const std::vector<int32_t> cliffParent = plane(7, [](int x, int y) { return cliffSea(x + 7, y) ? 0 : cliffLand(x, y); });
    const std::vector<int32_t> cliff = upsampleShadow(cliffParent, 7, 7, 1, 1);
    const std::vector<int16_t> steps = cliffResiduals(7, cliffParent, cliff);
    const std::vector<uint8_t> pinnedSteps = {0x50, 0x59, 0x52, 0x43, 0x07, 0x00, 0x04, 0x03, 0x00, 0x05, 0x01, 0x15, 0x57,
                                              0x56, 0x24, 0xc6, 0x88, 0xa5, 0x7a, 0x21, 0x9e, 0xde, 0x78, 0x6b, 0x06, 0xde,
                                              0x00, 0x35, 0x42, 0x4d, 0xea, 0xba, 0x94, 0xb2, 0x79, 0x9b, 0x00};
    EXPECT_EQ(encodeContextParentMode(steps, 7, cliff, 4), pinnedSteps);
    EXPECT_EQ(decodeContextResiduals(pinnedSteps, 7, "tile", cliff), steps);
}

// max(heights - 1500, 0): land rising from a flat sea at 0 m.
std::vector<float> coastHeights(int side) {
    std::vector<float> h = test::syntheticHeights(side, side, 2500.0f);
    for (float& v : h) {
        v = std::max(v - 1500.0f, 0.0f);
    }
    return h;
}

void expectSameResiduals(const ResidualFileReader& a, const ResidualFileReader& b) {
    ASSERT_EQ(b.header().maxLevel, a.header().maxLevel);
    test::forEachTile(a.header(), [&](int l, int tx, int ty) {
        EXPECT_EQ(a.readTile(l, tx, ty), b.readTile(l, tx, ty)) << l << "," << tx << "," << ty;
    });
}

// A coast (coastHeights by default) as a GeoTIFF, its Deflate file (deflate.dat), and the
// options that made it: 48-tiles, a 12-interval root, scale 1.
struct Coast {
    test::TempDir dir;
    std::string input = dir.file("coast.tif");
    DemEncodeOptions o;
    explicit Coast(const std::vector<float>& heights = coastHeights(193)) {
        test::writeFloatRaster(input, 193, 193, heights);
        o.tileSize = 48;
        o.rootTileSize = 12;
        o.scale = 1.0;
        encodeDem(input, dir.file("deflate.dat"), o);
        o.tiles.codec = ResidualCodec::Context;
    }
};

TEST(ParentMode, CoastFilesAreSmallerHoldTheSameResidualsAndVerify) {
    Coast coast;
    test::TempDir& dir = coast.dir;
    const std::string& input = coast.input;
    DemEncodeOptions& o = coast.o;
    o.threads = 2;
    const DemReport context = encodeDem(input, dir.file("context.dat"), o);
    o.threads = 1;
    encodeDem(input, dir.file("context-1.dat"), o);
    EXPECT_EQ(test::bytesOf(dir.file("context.dat")), test::bytesOf(dir.file("context-1.dat")));
    EXPECT_EQ(context.bytes, test::bytesOf(dir.file("context.dat")).size());
    EXPECT_TRUE(verifyDem(dir.file("context.dat"), input, DemVerifyOptions{}).ok());

    const auto deflate = ResidualFileReader::open(dir.file("deflate.dat"));
    const auto coded = ResidualFileReader::open(dir.file("context.dat"));
    expectSameResiduals(*deflate, *coded);
    // Each tile in the parent mode is smaller than version 2 would store it; the others are version 2's.
    const ResidualHeader& h = coded->header();
    int parentTiles = 0;
    uint64_t stored = 0, asVersion2 = 0;
    test::forEachTile(h, [&](int l, int tx, int ty) {
        const std::vector<uint8_t> blob = coded->readTileBytes(l, tx, ty);
        const std::vector<uint8_t> version2 = encodeContextResiduals(deflate->readTile(l, tx, ty), h.tileSamples(l));
        stored += blob.size();
        asVersion2 += version2.size();
        if (contextBlobNeedsParent(blob)) {
            ++parentTiles;
            EXPECT_LT(blob.size(), version2.size());
        } else {
            EXPECT_EQ(blob, version2);
        }
    });
    EXPECT_GT(parentTiles, 4);
    EXPECT_LT(stored * 100, asVersion2 * 97) << stored << " against " << asVersion2;
    // Recoding gives the same tiles (in the recoder's order) and the same residuals.
    ResidualRecodeOptions ro;
    ro.tiles.codec = ResidualCodec::Context;
    const ResidualRecodeReport recoded = recodeResidualFile(dir.file("deflate.dat"), dir.file("recoded.dat"), ro);
    EXPECT_EQ(recoded.bytes, context.bytes);
    expectSameResiduals(*deflate, *ResidualFileReader::open(dir.file("recoded.dat")));
}

// The heights below 1500 flooded to 0: a sea behind cliffs of 1500 m and more. Mode 4 is chosen
// where smaller, and saves at least 5 % of those tiles' mode-3 bytes.
std::vector<float> floodedHeights(int side) {
    std::vector<float> h = test::syntheticHeights(side, side, 2500.0f);
    for (float& v : h) {
        v = v < 1500.0f ? 0.0f : v;
    }
    return h;
}

TEST(ParentMode, SeasBehindCliffsTakeTheStepMode) {
    Coast flooded(floodedHeights(193));
    test::TempDir& dir = flooded.dir;
    encodeDem(flooded.input, dir.file("context.dat"), flooded.o);
    EXPECT_TRUE(verifyDem(dir.file("context.dat"), flooded.input, DemVerifyOptions{}).ok());
    const auto deflate = ResidualFileReader::open(dir.file("deflate.dat"));
    const auto coded = ResidualFileReader::open(dir.file("context.dat"));
    expectSameResiduals(*deflate, *coded);
    const ResidualHeader& h = coded->header();
    int stepTiles = 0;
    uint64_t stored = 0, asMode3 = 0;
    test::forEachTile(h, [&](int l, int tx, int ty) {
        const std::vector<uint8_t> blob = coded->readTileBytes(l, tx, ty);
        if (contextBlobNeedsParent(blob) && blob[6] == 4) {
            ++stepTiles;
            const std::vector<uint8_t> mode3 =
                encodeContextParentMode(deflate->readTile(l, tx, ty), h.tileSamples(l), coded->parentPlane(l, tx, ty), 3);
            EXPECT_LT(blob.size(), mode3.size()) << l << "," << tx << "," << ty;
            stored += blob.size();
            asMode3 += mode3.size();
        }
    });
    EXPECT_GT(stepTiles, 4);
    EXPECT_LT(stored * 100, asMode3 * 95) << stored << " against " << asMode3;
}

// A set's files each decode alone (each from its own root), and producers of another tile size
// (window reads, k > 0) rebuild the single Deflate file's heights bit for bit.
TEST(ParentMode, SetsAndRuntimeTilesOfAnotherSizeGiveTheSameHeights) {
    Coast coast;
    test::TempDir& dir = coast.dir;
    const std::string& input = coast.input;
    DemEncodeOptions& o = coast.o;
    const uint64_t whole = encodeDem(input, dir.file("whole.dat"), o).bytes;
    o.maxFileBytes = whole / 3;
    const DemReport set = encodeDem(input, dir.file("set.dat"), o);
    ASSERT_GT(set.files.size(), 2u);
    for (const auto& [name, bytes] : set.files) {
        EXPECT_LE(bytes, o.maxFileBytes) << name;
    }
    EXPECT_TRUE(verifyDem(dir.file("set.dat"), input, DemVerifyOptions{}).ok());
    const auto single = ResidualFileReader::open(dir.file("deflate.dat"));
    for (const int n : {48, 12}) {
        ElevationProducerOptions eo;
        eo.tileSize = n;
        const auto fromSet = openElevationSet(dir.file("set.dat"), eo);
        ResidualProducerOptions rp;
        rp.delta = elevationDelta(single->header(), n);
        ElevationProducer fromFile(std::make_shared<ResidualProducer>(dir.file("deflate.dat"), std::vector<std::string>{}, rp), eo);
        ASSERT_EQ(fromSet->maxLevel(), fromFile.maxLevel());
        const int deepest = fromFile.maxLevel();
        for (const auto& [l, tx, ty] : {std::tuple{deepest, 0, 0}, {deepest, (1 << deepest) - 1, 1}, {deepest - 1, 1, 0}, {0, 0, 0}}) {
            const auto a = fromSet->tile(l, tx, ty);
            const auto b = fromFile.tile(l, tx, ty);
            ASSERT_EQ(a->zf.size(), b->zf.size());
            EXPECT_EQ(std::memcmp(a->zf.data(), b->zf.data(), a->zf.size() * sizeof(float)), 0) << n << ": " << l << "," << tx << "," << ty;
        }
    }
}

} // namespace
} // namespace pyramid
