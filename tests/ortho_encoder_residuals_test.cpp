// preprocessOrtho as a library, the colour residuals: rebuilt bit for bit by the CPU producer, a
// tile of one colour shared only under a parent of its colour, and the residual Deflate level,
// given or chosen per tile, trading time for bytes only.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_levels.hpp"
#include "libpyramid/encode/ortho/ortho_tile_encoder.hpp"
#include "libpyramid/filters/colour_upsample.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "tests/support/ortho_images.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::orthoImage;
using test::smallOrtho;

TEST(OrthoEncoder, ColourResidualsRebuildBitForBit) {
    for (const TilePolicy compression : {TilePolicy::Deflate, TilePolicy::Jpeg}) {
        test::TempDir dir;
        const auto px = orthoImage(100, 80, 3, 240);
        test::writeImage(dir.file("in.png"), 100, 80, 3, px, false);
        OrthoEncodeOptions o = smallOrtho();
        o.levels.tileSize = 8; // levels 0..4: both the in-memory levels and the subtrees
        o.writeTiff = o.writeDxt = false;
        o.residualCompression = compression;
        std::map<std::tuple<int, int, int>, std::vector<uint8_t>> recon;
        o.colourReconstruction = [&](int l, int tx, int ty, const std::vector<uint8_t>& r) { recon[{l, tx, ty}] = r; };
        const OrthoReport report = encodeOrtho(dir.file("in.png"), dir.file("out"), o);
        ASSERT_EQ(report.maxLevel, 4);
        ASSERT_EQ(static_cast<int64_t>(recon.size()), report.tiles);
        ColourProducer producer(std::make_shared<OrthoProducer>(dir.file("out/residuals/RGB.dat")));
        for (const auto& [key, tile] : recon) {
            const auto [l, tx, ty] = key;
            ASSERT_EQ(*producer.tile(l, tx, ty), tile) << "tile (" << l << "," << tx << "," << ty << ")";
        }
        for (const OrthoLevelReport& l : report.levels) {
            if (compression == TilePolicy::Deflate) {
                EXPECT_LE(l.residualMaxError, 1); // residuals are stored in steps of 2
            }
        }
    }
}

// A tile of one colour is encoded once per colour and its bytes are shared, but only under a
// parent whose rebuilt colours are that colour too (its residuals are then 128 everywhere).
// Under a parent of another colour, whether the parent is itself a shared tile or not, the tile
// is encoded as itself, and its stored residuals rebuild it from that parent.
TEST(OrthoEncoder, AOneColourTileIsSharedOnlyUnderAParentOfItsColour) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 32, 32, 3, std::vector<uint16_t>(32 * 32 * 3, 100), false);
    OrthoEncodeOptions o = smallOrtho();
    o.levels.tileSize = 8;
    const OrthoLevels levels(dir.file("in.png"), o.levels);
    const OrthoTileEncoder encoder(levels, o);
    const int side = 8 + 4;
    const size_t bytes = static_cast<size_t>(side) * side * 3;
    const auto tileOf = [&](uint8_t colour, int tx, int ty) {
        TrueTile t;
        t.level = 2;
        t.tx = tx;
        t.ty = ty;
        t.pixels = Image8(side, side, 3);
        std::fill(t.pixels.pixels.begin(), t.pixels.pixels.end(), colour);
        return t;
    };
    // What a reader rebuilds from the tile's stored residuals and its parent.
    const auto rebuilt = [&](const EncodedOrthoTile& e, const std::vector<uint8_t>& parent, int tx, int ty) {
        const std::vector<uint8_t> residual = decodeOrthoTiff(*e.residual, side, 3, "residual tile");
        std::vector<uint8_t> out(bytes);
        upsampleColour(parent.data(), 8, 3, tx, ty, residual.data(), out.data());
        return out;
    };
    const std::vector<uint8_t> hundred(bytes, 100), ninetyEight(bytes, 98);
    const EncodedOrthoTile first = encoder.encode(tileOf(100, 0, 0), &hundred);
    const EncodedOrthoTile other = encoder.encode(tileOf(98, 1, 0), &ninetyEight);
    ASSERT_TRUE(first.uniform && other.uniform);
    EXPECT_EQ(*first.recon, hundred);

    // Under a shared tile of its colour: the first tile's bytes, shared.
    const EncodedOrthoTile shared = encoder.encode(tileOf(100, 1, 1), first.recon.get());
    EXPECT_EQ(shared.residual, first.residual);
    EXPECT_EQ(shared.tiff, first.tiff);
    EXPECT_EQ(rebuilt(shared, *first.recon, 1, 1), hundred);

    // Under a shared tile of 98, under a parent of 98 that is not shared, and under a parent of
    // many colours whose first pixel is 100: its own residuals, which rebuild it from that parent.
    std::vector<uint8_t> mixed(bytes);
    for (size_t k = 0; k < bytes; ++k) {
        mixed[k] = static_cast<uint8_t>(k < 3 ? 100 : 60 + (k * 37) % 90);
    }
    for (const std::vector<uint8_t>* parent :
         std::initializer_list<const std::vector<uint8_t>*>{other.recon.get(), &ninetyEight, &mixed}) {
        const EncodedOrthoTile own = encoder.encode(tileOf(100, 2, 3), parent);
        EXPECT_NE(*own.residual, *first.residual);
        EXPECT_EQ(rebuilt(own, *parent, 2, 3), *own.recon);
        if (parent != &mixed) {
            EXPECT_EQ(*own.recon, hundred);
        }
        EXPECT_EQ(*own.tiff, *first.tiff); // the same TIFF tile, which does not depend on the parent
    }
}

// So does the residual Deflate level: the residual tiles decode to the same residuals, and
// the reports' errors (closed loop over them) are the same.
TEST(OrthoEncoder, ResidualDeflateLevelsDecodeToTheSameResiduals) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 100, 60, 3, orthoImage(100, 60, 3, 255), false);
    OrthoEncodeOptions o = smallOrtho();
    o.writeDxt = o.writeTiff = false;
    std::vector<OrthoReport> reports;
    for (const int level : {1, 2, 12}) {
        o.residualDeflateLevel = level;
        reports.push_back(encodeOrtho(dir.file("in.png"), dir.file("r" + std::to_string(level)), o));
    }
    EXPECT_GT(reports[0].bytes.at(0), reports[2].bytes.at(0));
    EXPECT_GE(reports[1].bytes.at(0), reports[2].bytes.at(0));
    const auto fastest = OrthoFileReader::open(dir.file("r1/residuals/RGB.dat"));
    const auto smallest = OrthoFileReader::open(dir.file("r12/residuals/RGB.dat"));
    for (int l = 0; l <= fastest->header().maxLevel; ++l) {
        for (int ty = 0; ty < (1 << l); ++ty) {
            for (int tx = 0; tx < (1 << l); ++tx) {
                ASSERT_EQ(fastest->readTile(l, tx, ty), smallest->readTile(l, tx, ty)) << l << "," << tx << "," << ty;
            }
        }
        EXPECT_EQ(reports[0].levels[static_cast<size_t>(l)].residualRmsError,
                  reports[2].levels[static_cast<size_t>(l)].residualRmsError);
    }
    for (const int level : {-1, 13}) {
        o.residualDeflateLevel = level;
        EXPECT_THROW(encodeOrtho(dir.file("in.png"), dir.file("bad"), o), Error);
        EXPECT_FALSE(std::filesystem::exists(dir.file("bad")));
    }
}

// The default residual Deflate level (0) is chosen per tile: level 2 where the stored residuals
// are smooth (mean distance from 128 below 1/2) and for the root's colours, level 1 where they
// are grainy. Each tile is the very blob that level would give.
TEST(OrthoEncoder, DefaultResidualDeflateLevelIsChosenPerTileFromItsResiduals) {
    test::TempDir dir;
    const int W = 64;
    // West half a gentle gradient (residuals 128), east half grain: both kinds of tile.
    std::vector<uint16_t> px(static_cast<size_t>(W) * W * 3);
    uint32_t state = 12345;
    for (int y = 0; y < W; ++y) {
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 3; ++c) {
                state = state * 1664525u + 1013904223u;
                px[(static_cast<size_t>(y) * W + x) * 3 + c] =
                    static_cast<uint16_t>(x < W / 2 ? 60 + x + 2 * c : 40 + (state >> 24) % 160);
            }
        }
    }
    test::writeImage(dir.file("in.png"), W, W, 3, px, false);
    OrthoEncodeOptions o = smallOrtho();
    o.writeDxt = o.writeTiff = false;
    for (const int level : {0, 1, 2}) {
        o.residualDeflateLevel = level;
        encodeOrtho(dir.file("in.png"), dir.file("r" + std::to_string(level)), o);
    }
    const auto chosen = OrthoFileReader::open(dir.file("r0/residuals/RGB.dat"));
    const auto one = OrthoFileReader::open(dir.file("r1/residuals/RGB.dat"));
    const auto two = OrthoFileReader::open(dir.file("r2/residuals/RGB.dat"));
    int smooth = 0, grainy = 0;
    for (int l = 0; l <= chosen->header().maxLevel; ++l) {
        for (int ty = 0; ty < (1 << l); ++ty) {
            for (int tx = 0; tx < (1 << l); ++tx) {
                const std::vector<uint8_t> stored = chosen->readTile(l, tx, ty);
                uint64_t distance = 0;
                for (const uint8_t v : stored) {
                    distance += static_cast<uint64_t>(std::abs(static_cast<int>(v) - 128));
                }
                const bool levelTwo = l == 0 || 2 * distance < stored.size();
                const auto blob1 = one->readTileBytes(l, tx, ty);
                const auto blob2 = two->readTileBytes(l, tx, ty);
                EXPECT_EQ(chosen->readTileBytes(l, tx, ty), levelTwo ? blob2 : blob1) << l << "," << tx << "," << ty;
                if (l > 0 && blob1 != blob2) {
                    ++(levelTwo ? smooth : grainy);
                }
            }
        }
    }
    EXPECT_GT(smooth, 0);
    EXPECT_GT(grainy, 0);
}

} // namespace
} // namespace pyramid
