// The residual tile codecs (formats/residual_codec.hpp): the context coder's round trips, its
// pinned bytes and its refusal of damaged blobs; the compatible TIFF layouts that every libtiff
// reader decodes to the same bytes; and whole files in each codec, whose residuals, heights and
// verification are the same, in the library and the programs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_tiff_plain.hpp"
#include "formats/residual_file.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/residual/residual_recode.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/residual_tiles.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

std::vector<int16_t> noise(int size, int spread, uint32_t seed) { return test::residualNoise(size, spread, seed); }

// Heights of a smooth slope with bumps: what a root tile stores (its residuals are heights).
std::vector<int16_t> slope(int size) {
    std::vector<int16_t> v(static_cast<size_t>(size) * static_cast<size_t>(size));
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            v[static_cast<size_t>(y * size + x)] =
                static_cast<int16_t>(1000 + 37 * x - 21 * y + static_cast<int>(40.0 * std::sin(0.3 * x) * std::cos(0.2 * y)));
        }
    }
    return v;
}

std::vector<int16_t> roundTrip(const std::vector<int16_t>& v, int size) {
    const std::vector<uint8_t> blob = encodeContextResiduals(v, size);
    EXPECT_TRUE(isContextResidualBlob(blob));
    return decodeContextResiduals(blob, size, "tile");
}

TEST(ContextResiduals, RoundTripsEveryKindOfTile) {
    for (const int size : {1, 2, 5, 29, 197}) {
        // Every mode of every version, on the int16 extremes and noise.
        for (const auto& [version, modes] : {std::pair{0, 2}, std::pair{1, 3}, std::pair{2, 3}}) {
            for (int mode = 0; mode < modes; ++mode) {
                for (const std::vector<int16_t>& v : {noise(size, 300, 4), noise(size, 32767, 5)}) {
                    EXPECT_EQ(decodeContextResiduals(encodeContextResiduals(v, size, version, mode), size, "t"), v)
                        << size << " " << version << " " << mode;
                }
            }
        }
        EXPECT_EQ(roundTrip(noise(size, 3, 1), size), noise(size, 3, 1)) << size;
        EXPECT_EQ(roundTrip(noise(size, 300, 2), size), noise(size, 300, 2)) << size;
        EXPECT_EQ(roundTrip(noise(size, 32767, 3), size), noise(size, 32767, 3)) << size;
        EXPECT_EQ(roundTrip(slope(size), size), slope(size)) << size;
        const std::vector<int16_t> zeros(static_cast<size_t>(size * size), 0);
        EXPECT_EQ(roundTrip(zeros, size), zeros) << size;
        // The int16 extremes side by side: differences of 65535 either way, the longest escapes.
        std::vector<int16_t> extremes(static_cast<size_t>(size * size));
        for (size_t k = 0; k < extremes.size(); ++k) {
            extremes[k] = (k + k / static_cast<size_t>(size)) % 2 == 0 ? int16_t{-32768} : int16_t{32767};
        }
        EXPECT_EQ(roundTrip(extremes, size), extremes) << size;
    }
}

TEST(ContextResiduals, HeightsAreCodedAgainstTheMedianPredictorAndNoiseAsItIs) {
    const std::vector<uint8_t> heights = encodeContextResiduals(slope(64), 64);
    const std::vector<uint8_t> residuals = encodeContextResiduals(noise(64, 4, 7), 64);
    EXPECT_EQ(heights[6], 1);   // mode: median prediction
    EXPECT_EQ(residuals[6], 0); // mode: as they are
    EXPECT_EQ(heights[7], 2);   // version
    // Far below 16 bits a sample: near the 3.17 bits of 9 equally likely values.
    EXPECT_LT(residuals.size(), 64u * 64u * 7u / 16u);
    EXPECT_LT(heights.size(), residuals.size());
}

// The format's bytes, pinned: a change of the coder or its constants (doc/format.md, 1.8) fails
// here before it reaches a file. Version 0's and 1's blobs stay readable as they were written.
TEST(ContextResiduals, BytesOfAKnownTileArePinned) {
    const std::vector<int16_t> tile = {0, 1, -1, 2, 0, 0, 40, -3, 5};
    const std::vector<uint8_t> version0 = {0x50, 0x59, 0x52, 0x43, 0x03, 0x00, 0x00, 0x00, 0x00, 0x00,
                                           0x7a, 0x67, 0x99, 0x8e, 0xf7, 0xcd, 0xfa, 0x19, 0x7a};
    EXPECT_EQ(decodeContextResiduals(version0, 3, "tile"), tile);
    EXPECT_EQ(encodeContextResiduals(tile, 3, 0), version0);

    const std::vector<int16_t> grid = {0, 3, 0, -2, 0, 4, 6, 1, -5, 2, 0, 2, 0, 1, 0, -3, -4, 2, 7, 1, 0, -1, 0, 300, 0};
    const std::vector<uint8_t> mode0 = {0x50, 0x59, 0x52, 0x43, 0x05, 0x00, 0x00, 0x01, 0x00, 0x4e, 0x24, 0x79,
                                        0xfd, 0xd9, 0x1f, 0x16, 0x88, 0x1d, 0xf0, 0xdf, 0x97, 0xd5, 0x0f, 0x00};
    const std::vector<uint8_t> mode2 = {0x50, 0x59, 0x52, 0x43, 0x05, 0x00, 0x02, 0x01, 0x00, 0x4d, 0xe4, 0x3f,
                                        0xde, 0x30, 0x67, 0x74, 0xd7, 0xa7, 0x76, 0xe0, 0xfd, 0x7d, 0x80, 0x00};
    EXPECT_EQ(encodeContextResiduals(grid, 5, 1), mode0); // modes 0 and 2 tie: the first is kept
    EXPECT_EQ(encodeContextResiduals(grid, 5, 1, 2), mode2);
    EXPECT_EQ(decodeContextResiduals(mode0, 5, "tile"), grid);
    EXPECT_EQ(decodeContextResiduals(mode2, 5, "tile"), grid);
}

// Version 1's mode 2 predicts beyond int16: the value 32767 - (-36864) needs an escape of 17
// low bits, coded as bit 16 and then the low 16.
TEST(ContextResiduals, TheLongestEscapeRoundTrips) {
    std::vector<int16_t> tile(9 * 9, 0);
    tile[3 * 9 + 2] = -32768; // left of (3, 3), a sample of odd column and row
    tile[2 * 9 + 3] = -32768; // below it
    tile[3 * 9 + 3] = 32767;  // predicted as (12 * -32768 + 6 * -32768 + 8) >> 4 = -36864
    EXPECT_EQ(decodeContextResiduals(encodeContextResiduals(tile, 9, 1, 2), 9, "tile"), tile);
}

TEST(ContextResiduals, DamagedBlobsAreRefusedWithTheirName) {
    const std::vector<int16_t> tile = noise(21, 500, 11);
    const std::vector<uint8_t> blob = encodeContextResiduals(tile, 21);
    const auto refused = [](const std::vector<uint8_t>& b, int size, const std::string& mention) {
        test::expectContextBlobRefused(b, size, "DEM.dat: tile (2,1,0)", mention);
    };
    refused(blob, 20, "21 samples a side, expected 20");
    for (size_t cut = 0; cut < blob.size(); cut += 7) {
        refused(std::vector<uint8_t>(blob.begin(), blob.begin() + static_cast<std::ptrdiff_t>(cut)), 21, "");
    }
    std::vector<uint8_t> longer = blob;
    longer.push_back(0);
    refused(longer, 21, "1 bytes after the end");
    std::vector<uint8_t> mode = blob;
    mode[6] = 3;
    refused(mode, 21, "unknown kind (mode 3, version 2)");
    std::vector<uint8_t> version = blob;
    version[7] = 3;
    refused(version, 21, "unknown kind");
    std::vector<uint8_t> older = encodeContextResiduals(tile, 21, 0);
    older[6] = 2; // mode 2 is from version 1 on
    refused(older, 21, "unknown kind (mode 2, version 0)");
    std::vector<uint8_t> start = blob;
    start[8] = 1;
    refused(start, 21, "damaged stream start");
    // Any byte changed: an error or other residuals, never a crash (the fuzz target goes further).
    for (size_t k = 8; k < blob.size(); ++k) {
        std::vector<uint8_t> flipped = blob;
        flipped[k] ^= 0x5a;
        try {
            EXPECT_EQ(decodeContextResiduals(flipped, 21, "t").size(), tile.size());
        } catch (const Error&) {
        }
    }
}

// Every compatible layout decodes, through plain libtiff as the original runtime reads it, to
// the bytes of the int16 residuals.
TEST(ResidualTiff, CompatibleLayoutsGiveTheSameStripBytes) {
    const std::vector<int16_t> tile = slope(37);
    std::vector<uint8_t> bytes(tile.size() * 2);
    std::memcpy(bytes.data(), tile.data(), bytes.size());
    for (const auto layout : {ResidualTiffLayout::TwoBytes, ResidualTiffLayout::OneShort}) {
        for (const bool predictor : {false, true}) {
            const std::vector<uint8_t> blob = encodeResidualTiff(tile, 37, 9, layout, predictor);
            const TiffImage image = decodeTiff(blob, 37, 37, "tile");
            EXPECT_EQ(image.pixels, bytes) << static_cast<int>(layout) << predictor;
            EXPECT_EQ(image.bitsPerSample, layout == ResidualTiffLayout::OneShort ? 16 : 8);
            EXPECT_EQ(decodeResidualTiff(blob, 37, "tile"), tile);
        }
    }
}

TEST(ResidualCodec, SmallestIsNeverLargerAndEachCodecDecodes) {
    for (const std::vector<int16_t>& tile : {slope(53), noise(53, 9, 5)}) {
        ResidualTileCoding deflate{ResidualCodec::Deflate, 12};
        ResidualTileCoding smallest{ResidualCodec::Smallest, 0};
        ResidualTileCoding context{ResidualCodec::Context, 0};
        const auto d = encodeResidualBlob(tile, 53, deflate);
        const auto s = encodeResidualBlob(tile, 53, smallest);
        const auto c = encodeResidualBlob(tile, 53, context);
        EXPECT_LE(s.size(), d.size());
        EXPECT_LT(c.size(), s.size());
        EXPECT_EQ(describeResidualBlob(d), "deflate");
        EXPECT_EQ(describeResidualBlob(s), "deflate");
        EXPECT_EQ(describeResidualBlob(c), "context");
        for (const auto* blob : {&d, &s, &c}) {
            EXPECT_EQ(decodeResidualBlob(*blob, 53, "tile"), tile);
        }
    }
    // Heights: the predictor pays, so Smallest takes it.
    EXPECT_LT(encodeResidualBlob(slope(53), 53, {ResidualCodec::Smallest, 12}).size(),
              encodeResidualBlob(slope(53), 53, {ResidualCodec::Deflate, 12}).size());
}

TEST(ResidualCodec, NamesAndLevels) {
    for (const auto c : {ResidualCodec::Deflate, ResidualCodec::Smallest, ResidualCodec::Context}) {
        EXPECT_EQ(parseResidualCodec(residualCodecName(c)), c);
    }
    EXPECT_FALSE(parseResidualCodec("zstd"));
    EXPECT_EQ((ResidualTileCoding{ResidualCodec::Deflate, 0}).effectiveDeflateLevel(), 2);
    EXPECT_EQ((ResidualTileCoding{ResidualCodec::Smallest, 0}).effectiveDeflateLevel(), 12);
    EXPECT_EQ((ResidualTileCoding{ResidualCodec::Smallest, 6}).effectiveDeflateLevel(), 6);
    EXPECT_THROW((ResidualTileCoding{ResidualCodec::Deflate, 13}).validate(), OptionError);
    EXPECT_THROW((ResidualTileCoding{ResidualCodec::Context, 6}).validate(), OptionError);
}

// The same input in each codec: the same residuals in every tile (so the same heights), every
// level within scale/2, and the files in the expected order of size.
TEST(ResidualCodec, FilesOfEachCodecHoldTheSameResiduals) {
    test::TempDir dir;
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, 193, 193, test::syntheticHeights(193, 193, 2500.0f));
    DemEncodeOptions o;
    o.tileSize = 48;
    o.rootTileSize = 12;
    o.scale = 0.5;
    std::vector<uint64_t> bytes;
    for (const auto codec : {ResidualCodec::Deflate, ResidualCodec::Smallest, ResidualCodec::Context}) {
        o.tiles.codec = codec;
        const std::string out = dir.file(std::string(residualCodecName(codec)) + ".dat");
        const DemReport r = encodeDem(input, out, o);
        bytes.push_back(r.bytes);
        EXPECT_EQ(r.coding.codec, codec);
        const DemVerifyReport v = verifyDem(out, input, DemVerifyOptions{});
        EXPECT_TRUE(v.ok()) << residualCodecName(codec);
    }
    EXPECT_LT(bytes[1], bytes[0]);
    EXPECT_LT(bytes[2], bytes[1] * 3 / 4);
    const auto deflate = ResidualFileReader::open(dir.file("deflate.dat"));
    const ResidualHeader& h = deflate->header();
    int tiles = 0;
    for (const char* name : {"smallest.dat", "context.dat"}) {
        const auto other = ResidualFileReader::open(dir.file(name));
        ASSERT_EQ(other->header().maxLevel, h.maxLevel);
        for (int l = 0; l <= h.maxLevel; ++l) {
            for (int ty = 0; ty < h.tilesPerSide(l); ++ty) {
                for (int tx = 0; tx < h.tilesPerSide(l); ++tx) {
                    ASSERT_EQ(other->readTile(l, tx, ty), deflate->readTile(l, tx, ty)) << name << " " << l << "," << tx << "," << ty;
                    ++tiles;
                }
            }
        }
    }
    EXPECT_EQ(tiles, 2 * h.tileCount());
}

// A flat plain: residuals 0 below the root, so nearly every tile shares the bytes of one.
// Recoding keeps the sharing, the residuals and the header, in place too.
TEST(ResidualRecode, SharedTilesStaySharedAndInPlaceWorks) {
    test::TempDir dir;
    const std::string input = dir.file("flat.tif");
    test::writeFloatRaster(input, 193, 193, std::vector<float>(193 * 193, 250.0f));
    DemEncodeOptions o;
    o.tileSize = 24;
    o.rootTileSize = 12;
    const std::string original = dir.file("flat.dat");
    const DemReport built = encodeDem(input, original, o);
    ASSERT_GT(built.sharedTiles, 50);
    const std::string copy = dir.file("copy.dat");
    ResidualRecodeOptions ro;
    ro.tiles.codec = ResidualCodec::Context;
    ro.threads = 2;
    const ResidualRecodeReport context = recodeResidualFile(original, copy, ro);
    EXPECT_EQ(context.tiles, built.tiles);
    EXPECT_EQ(context.sharedTiles, built.sharedTiles);
    EXPECT_LT(context.bytes, context.inputBytes);
    ro.tiles = {ResidualCodec::Smallest, 9};
    ro.threads = 1;
    const ResidualRecodeReport back = recodeResidualFile(copy, copy, ro); // in place
    EXPECT_EQ(back.sharedTiles, built.sharedTiles);
    const auto a = ResidualFileReader::open(original);
    const auto b = ResidualFileReader::open(copy);
    EXPECT_EQ(b->header().maxLevel, a->header().maxLevel);
    EXPECT_EQ(b->header().scale, a->header().scale);
    for (int l = 0; l <= a->header().maxLevel; ++l) {
        for (int ty = 0; ty < a->header().tilesPerSide(l); ++ty) {
            for (int tx = 0; tx < a->header().tilesPerSide(l); ++tx) {
                ASSERT_EQ(b->readTile(l, tx, ty), a->readTile(l, tx, ty)) << l << "," << tx << "," << ty;
                EXPECT_EQ(describeResidualBlob(b->readTileBytes(l, tx, ty)), "deflate");
            }
        }
    }
    // The same bytes for any thread count.
    ro.threads = 2;
    recodeResidualFile(original, dir.file("t2.dat"), ro);
    ro.threads = 1;
    recodeResidualFile(original, dir.file("t1.dat"), ro);
    EXPECT_EQ(test::readFile(dir.file("t1.dat")), test::readFile(dir.file("t2.dat")));
    EXPECT_THROW(recodeResidualFile(input, dir.file("x.dat"), ro), Error);
    EXPECT_FALSE(test::fileExists(dir.file("x.dat")));
}

TEST(ResidualCodec, ProgramsChooseReportAndDescribeTheCodec) {
    test::TempDir dir;
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, 97, 97, test::syntheticHeights(97, 97, 900.0f));
    const std::string dem = test::programPath("preprocessDem") + " '" + input + "' --tile-size 48 --root-tile-size 12 ";
    const auto context = test::run(dem + "-o '" + dir.file("c.dat") + "' --compression context --report -");
    ASSERT_EQ(context.exitCode, 0) << context.err;
    EXPECT_NE(context.err.find("warning: --compression context: the original Proland runtime cannot read"), std::string::npos)
        << context.err;
    const nlohmann::json report = nlohmann::json::parse(context.out);
    EXPECT_EQ(report["compression"], "context");
    EXPECT_TRUE(report["deflate_level"].is_null());
    const auto smallest = test::run(dem + "-q -o '" + dir.file("s.dat") + "' --compression smallest --report -");
    ASSERT_EQ(smallest.exitCode, 0) << smallest.err;
    EXPECT_EQ(smallest.err, "");
    EXPECT_EQ(nlohmann::json::parse(smallest.out)["deflate_level"], 12);
    const auto info = test::run(test::programPath("pyramid") + " info '" + dir.file("c.dat") + "' --json");
    ASSERT_EQ(info.exitCode, 0) << info.err;
    EXPECT_NE(info.out.find("\"context\""), std::string::npos) << info.out;
    const auto verify = test::run(test::programPath("pyramid") + " verify '" + dir.file("c.dat") + "' --source '" + input + "'");
    EXPECT_EQ(verify.exitCode, 0) << verify.err << verify.out;
    // Back to tiles the original runtime reads: the same residuals as the context file's.
    const auto recode = test::run(test::programPath("pyramid") + " recode -q '" + dir.file("c.dat") + "' -o '" +
                                  dir.file("d.dat") + "' --compression deflate --report -");
    ASSERT_EQ(recode.exitCode, 0) << recode.err;
    const nlohmann::json recoded = nlohmann::json::parse(recode.out);
    EXPECT_EQ(recoded["compression"], "deflate");
    EXPECT_EQ(recoded["deflate_level"], 2);
    EXPECT_GT(recoded["bytes"].get<uint64_t>(), recoded["input_bytes"].get<uint64_t>());
    const auto c = ResidualFileReader::open(dir.file("c.dat"));
    const auto d = ResidualFileReader::open(dir.file("d.dat"));
    const int M = d->header().maxLevel;
    EXPECT_EQ(describeResidualBlob(d->readTileBytes(M, 1, 0)), "deflate");
    EXPECT_EQ(describeResidualBlob(c->readTileBytes(M, 1, 0)), "context");
    for (int l = 0; l <= c->header().maxLevel; ++l) {
        EXPECT_EQ(d->readTile(l, 0, 0), c->readTile(l, 0, 0)) << l;
    }
    const auto notDem = test::run(test::programPath("pyramid") + " recode '" + input + "' -o '" + dir.file("x.dat") + "'");
    EXPECT_EQ(notDem.exitCode, 1);
    EXPECT_FALSE(test::fileExists(dir.file("x.dat")));
    for (const std::string bad : {"--compression zstd", "--deflate-level 13", "--compression context --deflate-level 6"}) {
        const auto r = test::run(dem + "-o '" + dir.file("bad.dat") + "' " + bad);
        EXPECT_NE(r.exitCode, 0) << bad;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad << "\n" << r.err;
        EXPECT_FALSE(test::fileExists(dir.file("bad.dat"))) << bad;
    }
}

} // namespace
} // namespace pyramid
