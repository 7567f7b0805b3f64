// Writer -> reader round trips for residual files (tests/support/pyramid_tiles.hpp): every tile
// exact, tiles in any order, small tiles below minLevel, a region root's coordinates, and the
// residual tiles other tools may store (1 x 16-bit TIFFs, the original 2 x 8-bit layout with any
// compression libtiff writes).
#include <gtest/gtest.h>
#include <tiffio.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_file.hpp"
#include "formats/tiff_tile.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/pyramid_tiles.hpp"

namespace pyramid {
namespace {

using test::residualsFor;
using test::residualTiles;
using test::TileId;

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

} // namespace
} // namespace pyramid
