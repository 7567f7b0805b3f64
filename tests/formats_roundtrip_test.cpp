// Writer -> reader round trips for residual and ortho files, every tile encoding, and the
// writers' guarantees: any tile order, shared identical tiles, atomic output, the 32-bit
// offset limit, no tile written twice.
//
// Tolerances (smooth gradients, the only content where they are meaningful):
//   JPEG quality 95: max abs difference <= 8 per sample (1 measured).
//   DXT1 / DXT5, cluster fit: max abs difference <= 8 per sample, alpha included (RGB565
//   endpoints and 4-level interpolation; 5 measured on these 3-levels-a-pixel gradients).
#include <gtest/gtest.h>
#include <tiffio.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <random>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"
#include "formats/tiff_tile.hpp"
#include "formats/tile_table.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

struct TileId {
    int level, tx, ty;
};

size_t entriesIn(const std::string& directory) {
    return static_cast<size_t>(
        std::distance(std::filesystem::directory_iterator(directory), std::filesystem::directory_iterator()));
}

// Every tile of levels [0, maxLevel], shuffled deterministically: writers must accept any order.
template <class TilesPerSide>
std::vector<TileId> shuffledTiles(int maxLevel, TilesPerSide tilesPerSide, unsigned seed) {
    std::vector<TileId> ids;
    for (int level = 0; level <= maxLevel; ++level) {
        const int side = static_cast<int>(tilesPerSide(level));
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                ids.push_back({level, tx, ty});
            }
        }
    }
    std::mt19937 rng(seed);
    std::shuffle(ids.begin(), ids.end(), rng);
    return ids;
}

std::vector<TileId> residualTiles(const ResidualHeader& h, unsigned seed) {
    return shuffledTiles(h.maxLevel, [&](int level) { return h.tilesPerSide(level); }, seed);
}

std::vector<TileId> orthoTiles(const OrthoHeader& h, unsigned seed) {
    return shuffledTiles(h.maxLevel, [](int level) { return int64_t{1} << level; }, seed);
}

// Residuals spanning the whole int16 range, different for every tile.
std::vector<int16_t> residualsFor(const ResidualHeader& h, const TileId& t) {
    const int n = h.tileSamples(t.level);
    std::vector<int16_t> v(static_cast<size_t>(n) * static_cast<size_t>(n));
    for (size_t k = 0; k < v.size(); ++k) {
        const long x = static_cast<long>(k) * 2654435761L + t.level * 1000 + t.tx * 77 + t.ty * 131;
        v[k] = static_cast<int16_t>(static_cast<uint16_t>(x & 0xffff));
    }
    return v;
}

// A smooth gradient, different for every tile (lossy codecs are only bounded on such content).
std::vector<uint8_t> smoothPixels(int size, int channels, const TileId& t) {
    std::vector<uint8_t> v(static_cast<size_t>(size) * size * channels);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            for (int c = 0; c < channels; ++c) {
                const int value = 30 + 3 * x + 2 * y + 25 * c + 7 * t.level + 5 * t.tx + 3 * t.ty;
                v[(static_cast<size_t>(y) * size + x) * channels + c] = static_cast<uint8_t>(std::min(value, 255));
            }
        }
    }
    return v;
}

int maxAbsDiff(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    EXPECT_EQ(a.size(), b.size());
    int worst = 0;
    for (size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
        worst = std::max(worst, std::abs(int(a[k]) - int(b[k])));
    }
    return worst;
}

// ----------------------------------------------------------------------------- residual files

TEST(ResidualRoundTrip, EveryTileExactWithSmallTilesBelowMinLevel) {
    test::TempDir dir;
    ResidualHeader h;
    h.minLevel = 2;
    h.maxLevel = 3;
    h.tileSize = 8;
    h.scale = 0.25f;
    ASSERT_EQ(h.tileSamples(0), 7);  // (8 >> 2) + 5
    ASSERT_EQ(h.tileSamples(1), 9);  // (8 >> 1) + 5
    ASSERT_EQ(h.tileSamples(2), 13); // tileSize + 5 from minLevel on
    const std::string path = dir.file("dem.dat");
    const auto tiles = residualTiles(h, 1);
    ASSERT_EQ(static_cast<int64_t>(tiles.size()), h.tileCount());
    {
        ResidualFileWriter writer(path, h);
        for (const TileId& t : tiles) {
            writer.writeTile(t.level, t.tx, t.ty, residualsFor(h, t));
        }
        writer.commit();
        EXPECT_EQ(writer.sharedTiles(), 0);
    }
    auto reader = ResidualFileReader::open(path);
    EXPECT_EQ(reader->header().minLevel, 2);
    EXPECT_EQ(reader->header().maxLevel, 3);
    EXPECT_EQ(reader->header().tileSize, 8);
    EXPECT_EQ(reader->header().scale, 0.25f);
    for (const TileId& t : tiles) {
        EXPECT_EQ(reader->readTile(t.level, t.tx, t.ty), residualsFor(h, t)) << t.level << "," << t.tx << "," << t.ty;
        EXPECT_EQ(describeTiff(reader->readTileBytes(t.level, t.tx, t.ty)), "deflate");
    }
    EXPECT_THROW(reader->readTile(1, 1, 0), Error); // one tile per level below minLevel
    EXPECT_THROW(reader->readTile(4, 0, 0), Error);
}

TEST(ResidualRoundTrip, RegionRootKeepsItsCoordinates) {
    test::TempDir dir;
    ResidualHeader h;
    h.maxLevel = 1;
    h.tileSize = 4;
    h.rootLevel = 3;
    h.rootTx = 5;
    h.rootTy = 2;
    const std::string path = dir.file("region.dat");
    {
        ResidualFileWriter writer(path, h);
        for (const TileId& t : residualTiles(h, 2)) {
            writer.writeTile(t.level, t.tx, t.ty, residualsFor(h, t));
        }
        writer.commit();
    }
    auto reader = ResidualFileReader::open(path);
    EXPECT_EQ(reader->header().rootLevel, 3);
    EXPECT_EQ(reader->header().rootTx, 5);
    EXPECT_EQ(reader->header().rootTy, 2);
    EXPECT_EQ(reader->readTile(1, 1, 1), residualsFor(h, {1, 1, 1}));
}

// A genuine 1 x 16-bit TIFF, written with libtiff itself (the documented layout).
std::vector<uint8_t> sixteenBitTiff(const std::string& path, const std::vector<uint16_t>& samples, int size,
                                    uint16_t sampleFormat, uint16_t compression = COMPRESSION_ADOBE_DEFLATE) {
    TIFF* t = TIFFOpen(path.c_str(), "w");
    EXPECT_NE(t, nullptr);
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(size));
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(size));
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, uint16_t{16});
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, uint16_t{1});
    TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, sampleFormat);
    TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, static_cast<uint32_t>(size));
    TIFFSetField(t, TIFFTAG_COMPRESSION, compression);
    std::vector<uint16_t> copy = samples; // libtiff may swab the buffer in place
    EXPECT_GE(TIFFWriteEncodedStrip(t, 0, copy.data(), static_cast<tmsize_t>(copy.size() * 2)), 0);
    TIFFClose(t);
    const std::string bytes = test::readFile(path);
    return std::vector<uint8_t>(bytes.begin(), bytes.end());
}

TEST(ResidualRoundTrip, GenuineSixteenBitTiffsDecodeSignedAndUnsigned) {
    test::TempDir dir;
    const int size = 9;
    std::vector<uint16_t> samples(size * size);
    for (size_t k = 0; k < samples.size(); ++k) {
        samples[k] = static_cast<uint16_t>(k * 811u + 32000u); // crosses 32767 -> negative residuals
    }
    std::vector<int16_t> expected(samples.size());
    std::transform(samples.begin(), samples.end(), expected.begin(),
                   [](uint16_t s) { return static_cast<int16_t>(s); });
    ASSERT_LT(*std::min_element(expected.begin(), expected.end()), 0);
    for (uint16_t format : {uint16_t(SAMPLEFORMAT_INT), uint16_t(SAMPLEFORMAT_UINT)}) {
        const auto blob = sixteenBitTiff(dir.file("tile.tif"), samples, size, format);
        const TiffImage image = decodeTiff(blob, size, size, "t");
        EXPECT_EQ(image.bitsPerSample, 16);
        EXPECT_EQ(image.channels, 1);
        EXPECT_EQ(image.signedSamples, format == SAMPLEFORMAT_INT);
        // Both sample formats carry the int16 bit pattern of the residual.
        EXPECT_EQ(decodeResidualTiff(blob, size, "t"), expected) << "sample format " << format;
        EXPECT_THROW(decodeResidualTiff(blob, size + 1, "t"), Error);
    }
    // And through a file: a 16-bit tile stored by writeTileBytes reads back as residuals.
    ResidualHeader h;
    h.maxLevel = 0;
    h.tileSize = 4;
    const std::string path = dir.file("dem16.dat");
    {
        ResidualFileWriter writer(path, h);
        writer.writeTileBytes(0, 0, 0, sixteenBitTiff(dir.file("tile.tif"), samples, size, SAMPLEFORMAT_INT));
        writer.commit();
    }
    EXPECT_EQ(ResidualFileReader::open(path)->readTile(0, 0, 0), expected);
}

// Residual tiles in the original 2 x 8-bit layout (low byte, high byte) with any compression
// libtiff writes: what other tools may store, which readers must accept.
std::vector<uint8_t> twoByteTiff(const std::string& path, const std::vector<int16_t>& residuals, int size,
                                 uint16_t compression) {
    TIFF* t = TIFFOpen(path.c_str(), "w");
    EXPECT_NE(t, nullptr);
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(size));
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(size));
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, uint16_t{8});
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, uint16_t{2});
    TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, static_cast<uint32_t>(size));
    TIFFSetField(t, TIFFTAG_COMPRESSION, compression);
    const uint16_t extra = EXTRASAMPLE_UNSPECIFIED;
    TIFFSetField(t, TIFFTAG_EXTRASAMPLES, uint16_t{1}, &extra);
    std::vector<uint8_t> bytes(residuals.size() * 2);
    for (size_t k = 0; k < residuals.size(); ++k) {
        const auto v = static_cast<uint16_t>(residuals[k]);
        bytes[2 * k] = static_cast<uint8_t>(v & 0xff);
        bytes[2 * k + 1] = static_cast<uint8_t>(v >> 8);
    }
    EXPECT_GE(TIFFWriteEncodedStrip(t, 0, bytes.data(), static_cast<tmsize_t>(bytes.size())), 0);
    TIFFClose(t);
    const std::string file = test::readFile(path);
    return std::vector<uint8_t>(file.begin(), file.end());
}

TEST(ResidualRoundTrip, EveryTiffCompressionOfBothLayouts) {
    test::TempDir dir;
    const int size = 9;
    std::vector<int16_t> residuals(size * size);
    std::vector<uint16_t> samples(residuals.size());
    for (size_t k = 0; k < residuals.size(); ++k) {
        residuals[k] = static_cast<int16_t>(static_cast<int>(k * 977) % 65536 - 32768);
        samples[k] = static_cast<uint16_t>(residuals[k]);
    }
    const struct {
        uint16_t code;
        const char* name;
    } compressions[] = {{COMPRESSION_ADOBE_DEFLATE, "deflate"}, {COMPRESSION_DEFLATE, "deflate-legacy"},
                        {COMPRESSION_LZW, "lzw"}, {COMPRESSION_NONE, "none"}, {COMPRESSION_PACKBITS, "packbits"}};
    ResidualHeader h;
    h.maxLevel = 0;
    h.tileSize = 4;
    for (const auto& c : compressions) {
        for (const bool twoBytes : {true, false}) {
            const auto blob = twoBytes ? twoByteTiff(dir.file("tile.tif"), residuals, size, c.code)
                                       : sixteenBitTiff(dir.file("tile.tif"), samples, size, SAMPLEFORMAT_INT, c.code);
            EXPECT_EQ(describeTiff(blob), c.name);
            EXPECT_EQ(decodeResidualTiff(blob, size, "t"), residuals) << c.name << (twoBytes ? " 2x8" : " 1x16");
            const std::string path = dir.file("dem.dat");
            {
                ResidualFileWriter writer(path, h);
                writer.writeTileBytes(0, 0, 0, blob);
                writer.commit();
            }
            EXPECT_EQ(ResidualFileReader::open(path)->readTile(0, 0, 0), residuals) << c.name;
        }
    }
}

// ----------------------------------------------------------------------------- ortho files

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

// ----------------------------------------------------------------------------- writer guarantees

TEST(WriterGuarantees, IdenticalTilesShareOneByteRange) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 2; // 21 tiles
    h.tileSize = 12;
    h.channels = 3;
    const std::string path = dir.file("shared.dat");
    const auto same = smoothPixels(h.tilePixels(), 3, {9, 9, 9});
    const auto other = smoothPixels(h.tilePixels(), 3, {0, 0, 0});
    uint64_t blobBytes = 0;
    {
        OrthoFileWriter writer(path, h);
        for (const TileId& t : orthoTiles(h, 5)) {
            writer.writeTile(t.level, t.tx, t.ty, t.level == 0 ? other : same);
        }
        EXPECT_EQ(writer.sharedTiles(), 19); // 20 identical tiles: stored once
        blobBytes = writer.bytesWritten();
        writer.commit();
    }
    const uint64_t headerAndTable = OrthoHeader::kBytes + 21u * 16u;
    EXPECT_EQ(std::filesystem::file_size(path), headerAndTable + blobBytes);
    auto reader = OrthoFileReader::open(path);
    const uint64_t sizeSame = reader->table().range(h.tileIndex(1, 0, 0)).size();
    const uint64_t sizeOther = reader->table().range(h.tileIndex(0, 0, 0)).size();
    EXPECT_EQ(blobBytes, sizeSame + sizeOther);
    EXPECT_EQ(reader->table().distinctRanges(), 2);
    const TileTable::Range first = reader->table().range(h.tileIndex(1, 0, 0));
    for (int64_t i = 1; i < h.tileCount(); ++i) {
        EXPECT_EQ(reader->table().range(i).begin, first.begin);
        EXPECT_EQ(reader->table().range(i).end, first.end);
    }
    EXPECT_EQ(reader->readTile(2, 3, 3), same);
    EXPECT_EQ(reader->readTile(0, 0, 0), other);
}

// The offset table is written in pieces of 65536 entries: every entry of a table of several
// pieces, the last one partial, is the range of its own tile's bytes.
TEST(WriterGuarantees, ATableOfManyPiecesHoldsEveryTilesRange) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 8; // 87381 tiles: one piece of the table and part of a second
    h.tileSize = 4;
    h.channels = 1;
    const std::string path = dir.file("many.dat");
    {
        OrthoFileWriter writer(path, h);
        for (int level = h.maxLevel; level >= 0; --level) { // every tile's bytes its own index, finest first
            for (int ty = 0; ty < (1 << level); ++ty) {
                for (int tx = 0; tx < (1 << level); ++tx) {
                    const auto i = static_cast<uint64_t>(h.tileIndex(level, tx, ty));
                    std::vector<uint8_t> blob(8);
                    for (int b = 0; b < 8; ++b) {
                        blob[static_cast<size_t>(b)] = static_cast<uint8_t>(i >> (8 * b));
                    }
                    writer.writeTileBytes(level, tx, ty, blob);
                }
            }
        }
        writer.commit();
    }
    const auto reader = OrthoFileReader::open(path);
    ASSERT_EQ(reader->table().tileCount(), 87381);
    for (int64_t i = 0; i < reader->table().tileCount(); ++i) {
        const std::vector<uint8_t> blob = reader->table().read(i);
        ASSERT_EQ(blob.size(), 8u) << "tile " << i;
        uint64_t value = 0;
        for (int b = 0; b < 8; ++b) {
            value |= static_cast<uint64_t>(blob[static_cast<size_t>(b)]) << (8 * b);
        }
        ASSERT_EQ(value, static_cast<uint64_t>(i)) << "tile " << i;
    }
}

// A tile given an earlier tile's bytes (writeTileSameAs) shares its range, as writing the same
// bytes does: the file is byte for byte the one written with the bytes every time. A tile not
// yet written cannot lend its bytes, and a tile is still written once.
TEST(WriterGuarantees, ATileGivenAnEarlierTilesBytesIsTheFileOfItsBytes) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 2; // 21 tiles
    h.tileSize = 8;
    h.channels = 3;
    const auto same = smoothPixels(h.tilePixels(), 3, {9, 9, 9});
    const auto blob = encodeTiff8(same, h.tilePixels(), h.tilePixels(), 3, TiffCompression::Deflate);
    for (const bool byReference : {false, true}) {
        OrthoFileWriter writer(dir.file(byReference ? "reference.dat" : "bytes.dat"), h);
        std::optional<std::array<int, 3>> first;
        for (const TileId& t : orthoTiles(h, 5)) {
            if (t.level == 1) {
                writer.writeTile(t.level, t.tx, t.ty, smoothPixels(h.tilePixels(), 3, t)); // tiles of their own
            } else if (byReference && first) {
                writer.writeTileSameAs(t.level, t.tx, t.ty, *first);
            } else {
                writer.writeTileBytes(t.level, t.tx, t.ty, blob);
                first = std::array<int, 3>{t.level, t.tx, t.ty};
            }
        }
        EXPECT_EQ(writer.sharedTiles(), 16); // 17 alike, stored once
        if (byReference) {
            EXPECT_THROW(writer.writeTileSameAs(2, 0, 0, *first), Error); // written twice
        }
        writer.commit();
    }
    EXPECT_EQ(test::readFile(dir.file("reference.dat")), test::readFile(dir.file("bytes.dat")));
    OrthoFileWriter writer(dir.file("unwritten.dat"), h);
    writer.writeTileBytes(0, 0, 0, blob);
    try {
        writer.writeTileSameAs(1, 0, 0, {2, 1, 1});
        ADD_FAILURE() << "a tile took the bytes of one not written";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("unwritten.dat"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("not written"), std::string::npos) << e.what();
    }
    EXPECT_THROW(writer.writeTileSameAs(1, 0, 0, {3, 0, 0}), Error); // no such tile
}

TEST(WriterGuarantees, ResidualTilesShareToo) {
    test::TempDir dir;
    ResidualHeader h;
    h.maxLevel = 1;
    h.tileSize = 4;
    const std::string path = dir.file("flat.dat");
    const std::vector<int16_t> flat(9 * 9, 0);
    {
        ResidualFileWriter writer(path, h);
        for (const TileId& t : residualTiles(h, 6)) {
            writer.writeTile(t.level, t.tx, t.ty, flat);
        }
        EXPECT_EQ(writer.sharedTiles(), 4);
        writer.commit();
    }
    auto reader = ResidualFileReader::open(path);
    EXPECT_EQ(reader->table().distinctRanges(), 1);
    EXPECT_EQ(std::filesystem::file_size(path), ResidualHeader::kBytes + 5u * 8u + reader->table().range(0).size());
    EXPECT_EQ(reader->readTile(1, 1, 0), flat);
}

TEST(WriterGuarantees, DestroyedWithoutCommitLeavesNothing) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = 4;
    h.channels = 1;
    {
        OrthoFileWriter writer(dir.file("never.dat"), h);
        writer.writeTile(0, 0, 0, smoothPixels(h.tilePixels(), 1, {0, 0, 0}));
        EXPECT_EQ(entriesIn(dir.path()), 1u); // the temporary, not the destination
        EXPECT_FALSE(test::fileExists(dir.file("never.dat")));
    }
    EXPECT_EQ(entriesIn(dir.path()), 0u);
}

TEST(WriterGuarantees, CommitWithAMissingTileThrowsAndLeavesNothing) {
    test::TempDir dir;
    ResidualHeader h;
    h.maxLevel = 1;
    h.tileSize = 4;
    const std::string path = dir.file("holes.dat");
    {
        ResidualFileWriter writer(path, h);
        for (const TileId& t : residualTiles(h, 7)) {
            if (!(t.level == 1 && t.tx == 0 && t.ty == 1)) {
                writer.writeTile(t.level, t.tx, t.ty, residualsFor(h, t));
            }
        }
        try {
            writer.commit();
            ADD_FAILURE() << "commit() accepted a missing tile";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), path + ": tile (1,0,1) was never written");
        }
        EXPECT_FALSE(test::fileExists(path));
    }
    EXPECT_EQ(entriesIn(dir.path()), 0u);
}

TEST(WriterGuarantees, MissingTilesAreNamedByEveryWriter) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 1;
    h.tileSize = 4;
    h.channels = 1;
    {
        OrthoFileWriter writer(dir.file("ortho.dat"), h);
        writer.writeTile(0, 0, 0, smoothPixels(h.tilePixels(), 1, {0, 0, 0}));
        writer.writeTile(1, 0, 0, smoothPixels(h.tilePixels(), 1, {1, 0, 0}));
        try {
            writer.commit();
            ADD_FAILURE() << "commit() accepted missing tiles";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), dir.file("ortho.dat") + ": tile (1,1,0) was never written");
        }
    }
    {
        TileTableWriter writer(dir.file("table.dat"), std::vector<uint8_t>(4, 0), 3, 8, 1000);
        writer.write(0, std::vector<uint8_t>(5, 1));
        writer.write(2, std::vector<uint8_t>(5, 1));
        try {
            writer.commit();
            ADD_FAILURE() << "commit() accepted a missing tile";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), dir.file("table.dat") + ": tile 1 was never written");
        }
    }
    EXPECT_EQ(entriesIn(dir.path()), 0u);
}

TEST(WriterGuarantees, SameTileTwiceIsAnError) {
    test::TempDir dir;
    ResidualHeader h;
    h.maxLevel = 0;
    h.tileSize = 4;
    ResidualFileWriter writer(dir.file("twice.dat"), h);
    writer.writeTile(0, 0, 0, residualsFor(h, {0, 0, 0}));
    try {
        writer.writeTile(0, 0, 0, residualsFor(h, {0, 0, 0}));
        ADD_FAILURE() << "a tile was written twice";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("tile 0 written twice"), std::string::npos) << e.what();
    }
    EXPECT_THROW(writer.writeTile(1, 0, 0, residualsFor(h, {0, 0, 0})), Error); // no such tile
}

TEST(WriterGuarantees, OffsetLimitIsAClearErrorNeverAWrap) {
    test::TempDir dir;
    const std::string path = dir.file("limit.dat");
    const std::vector<uint8_t> header(4, 0);
    const std::vector<uint8_t> a(60, 1), b(60, 2), c(40, 3);
    {
        TileTableWriter writer(path, header, 4, 4, 100);
        writer.write(0, a);
        writer.write(1, a); // shared: no new bytes
        try {
            writer.write(2, b); // would end at 120 > 100
            ADD_FAILURE() << "offset limit passed";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
            EXPECT_NE(what.find("100"), std::string::npos) << what;
        }
        EXPECT_FALSE(writer.written(2));
        writer.write(2, c); // exactly at the limit: fine
        writer.write(3, a);
        EXPECT_EQ(writer.bytesWritten(), 100u);
        writer.commit();
    }
    auto table = TileTable::open(path, header.size(), 4, 4);
    EXPECT_EQ(table->range(2).begin, 60u);
    EXPECT_EQ(table->range(2).end, 100u);
    EXPECT_EQ(table->read(3), a);
}

} // namespace
} // namespace pyramid
