// The residual TIFF reader without libtiff (formats/residual_tiff_plain.hpp) against libtiff,
// the reference: every tile of the original tools' DEM.dat, every layout libpyramid writes,
// TIFFs libtiff writes in other shapes (big-endian, several strips, uncompressed, the predictor),
// and damaged blobs, where it must either give libtiff's samples or decline.
#include <gtest/gtest.h>

#include <tiffio.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_codec.hpp"
#include "formats/residual_file.hpp"
#include "formats/residual_tiff_plain.hpp"
#include "formats/tiff_plain_writer.hpp"
#include "formats/tiff_strip_bytes.hpp"
#include "formats/tiff_tile.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

std::vector<int16_t> residuals(int size, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> d(-300, 300);
    std::vector<int16_t> v(static_cast<size_t>(size) * static_cast<size_t>(size));
    for (size_t k = 0; k < v.size(); ++k) {
        v[k] = static_cast<int16_t>(k % 7 == 0 ? d(rng) * 100 : d(rng)); // some beyond a byte
    }
    return v;
}

// The plain reader's samples, or nothing when it declines (or finds the stream damaged).
std::optional<std::vector<int16_t>> plain(const std::vector<uint8_t>& blob, int size) {
    std::vector<int16_t> out(static_cast<size_t>(size) * static_cast<size_t>(size));
    if (decodePlainResidualTiff(blob, size, out) != PlainDecode::Decoded) {
        return std::nullopt;
    }
    return out;
}

struct Shape {
    const char* mode = "w"; // "wb": big-endian
    uint16_t bits = 16, channels = 1;
    uint16_t compression = COMPRESSION_ADOBE_DEFLATE;
    uint16_t predictor = PREDICTOR_NONE;
    uint32_t rowsPerStrip = 0; // 0: one strip
};

// Residuals written by libtiff itself in `shape` (2 x 8 bits: low byte, then high byte).
std::vector<uint8_t> libtiffTile(const std::string& path, const std::vector<int16_t>& r, int size, const Shape& shape) {
    TIFF* t = TIFFOpen(path.c_str(), shape.mode);
    EXPECT_NE(t, nullptr);
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(size));
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(size));
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, shape.bits);
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, shape.channels);
    TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(t, TIFFTAG_COMPRESSION, shape.compression);
    if (shape.predictor != PREDICTOR_NONE) {
        TIFFSetField(t, TIFFTAG_PREDICTOR, shape.predictor);
    }
    const uint32_t rows = shape.rowsPerStrip == 0 ? static_cast<uint32_t>(size) : shape.rowsPerStrip;
    TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, rows);
    const size_t rowBytes = static_cast<size_t>(size) * 2;
    std::vector<uint8_t> bytes(r.size() * 2);
    for (size_t k = 0; k < r.size(); ++k) {
        const auto v = static_cast<uint16_t>(r[k]);
        if (shape.bits == 16) {
            std::memcpy(&bytes[2 * k], &v, 2); // native order: libtiff swaps for a big-endian file
        } else {
            bytes[2 * k] = static_cast<uint8_t>(v & 0xffu);
            bytes[2 * k + 1] = static_cast<uint8_t>(v >> 8);
        }
    }
    for (uint32_t s = 0; s * rows < static_cast<uint32_t>(size); ++s) {
        const size_t first = static_cast<size_t>(s) * rows;
        const size_t count = std::min<size_t>(rows, static_cast<size_t>(size) - first);
        EXPECT_GE(TIFFWriteEncodedStrip(t, s, &bytes[first * rowBytes], static_cast<tmsize_t>(count * rowBytes)), 0);
    }
    TIFFClose(t);
    const std::string file = test::readFile(path);
    return std::vector<uint8_t>(file.begin(), file.end());
}

TEST(PlainResidualTiff, DecodesEveryTileOfTheOriginalToolsAsLibtiffDoes) {
    const auto reader = ResidualFileReader::open(test::dataPath("proland/DEM.dat"));
    const ResidualHeader& h = reader->header();
    int tiles = 0;
    for (int level = 0; level <= h.maxLevel; ++level) {
        const int side = 1 << std::max(0, level - h.minLevel);
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                const std::vector<uint8_t> blob = reader->readTileBytes(level, tx, ty);
                const int size = h.tileSamples(level);
                const auto fast = plain(blob, size);
                ASSERT_TRUE(fast.has_value()) << level << " " << tx << " " << ty;
                ASSERT_TRUE(*fast == decodeResidualTiff(blob, size, "t")) << level << " " << tx << " " << ty;
                ++tiles;
            }
        }
    }
    EXPECT_EQ(tiles, 24);
}

TEST(PlainResidualTiff, DecodesEveryLayoutLibpyramidWrites) {
    const int size = 29;
    const std::vector<int16_t> r = residuals(size, 7);
    for (const auto layout : {ResidualTiffLayout::TwoBytes, ResidualTiffLayout::OneShort}) {
        for (const bool predictor : {false, true}) {
            for (const int level : {1, 2, 6, 12}) {
                const std::vector<uint8_t> blob = encodeResidualTiff(r, size, level, layout, predictor);
                const auto fast = plain(blob, size);
                ASSERT_TRUE(fast.has_value()) << predictor << " " << level;
                EXPECT_TRUE(*fast == r) << predictor << " " << level;
            }
        }
    }
    EXPECT_FALSE(plain(encodeResidualTiff(r, size, 2), size + 1).has_value()); // another size
}

TEST(PlainResidualTiff, OtherShapesLibtiffWritesDecodeTheSameOrAreLeftToLibtiff) {
    test::TempDir dir;
    const int size = 21;
    const std::vector<int16_t> r = residuals(size, 11);
    const std::vector<Shape> decoded = {
        {"wb", 16, 1, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 0}, // big-endian, predictor
        {"wb", 8, 2, COMPRESSION_DEFLATE, PREDICTOR_HORIZONTAL, 4},        // big-endian, strips of 4 rows
        {"w", 16, 1, COMPRESSION_NONE, PREDICTOR_NONE, 5},
        {"wb", 16, 1, COMPRESSION_NONE, PREDICTOR_NONE, 0},
        {"w", 8, 2, COMPRESSION_NONE, PREDICTOR_NONE, 0},
        {"w", 16, 1, COMPRESSION_DEFLATE, PREDICTOR_HORIZONTAL, 1},
    };
    for (size_t k = 0; k < decoded.size(); ++k) {
        const std::vector<uint8_t> blob = libtiffTile(dir.file("t.tif"), r, size, decoded[k]);
        ASSERT_TRUE(decodeResidualTiff(blob, size, "t") == r) << k;
        const auto fast = plain(blob, size);
        ASSERT_TRUE(fast.has_value()) << k;
        EXPECT_TRUE(*fast == r) << k;
    }
    // Other codecs go to libtiff, through the same entry point.
    for (const uint16_t codec : {uint16_t(COMPRESSION_LZW), uint16_t(COMPRESSION_PACKBITS)}) {
        const std::vector<uint8_t> blob = libtiffTile(dir.file("t.tif"), r, size, {"w", 16, 1, codec, PREDICTOR_NONE, 0});
        EXPECT_FALSE(plain(blob, size).has_value()) << codec;
        EXPECT_TRUE(decodeResidualBlob(blob, size, "t") == r) << codec;
    }
}

// A damaged blob decodes to libtiff's samples, or is declined, and the codec entry point then
// gives libtiff's answer (the same samples, or the same error); or its Deflate stream is found
// corrupt, which the entry point refuses even where libtiff, which stops once the strip is full
// and never reads the checksum, would decode it.
TEST(PlainResidualTiff, DamagedBlobsGiveLibtiffsAnswerOrAreRefused) {
    const int size = 29;
    const std::vector<int16_t> r = residuals(size, 3);
    std::mt19937 rng(5);
    int declined = 0, same = 0, damaged = 0;
    for (const bool predictor : {false, true}) {
        const std::vector<uint8_t> good = encodeResidualTiff(r, size, 6, ResidualTiffLayout::TwoBytes, predictor);
        for (int trial = 0; trial < 300; ++trial) {
            std::vector<uint8_t> blob = good;
            if (trial % 3 == 0) {
                blob.resize(std::uniform_int_distribution<size_t>(0, good.size() - 1)(rng)); // truncated
            } else {
                const size_t at = std::uniform_int_distribution<size_t>(0, good.size() - 1)(rng);
                blob[at] = static_cast<uint8_t>(blob[at] ^ (1u << (trial % 8)));
            }
            std::optional<std::vector<int16_t>> reference;
            std::string refused;
            try {
                reference = decodeResidualTiff(blob, size, "tile");
            } catch (const Error& e) {
                refused = e.what();
            }
            std::vector<int16_t> fast(static_cast<size_t>(size) * static_cast<size_t>(size));
            const PlainDecode status = decodePlainResidualTiff(blob, size, fast);
            if (status == PlainDecode::Damaged) {
                ++damaged;
                EXPECT_THROW(decodeResidualBlob(blob, size, "tile"), Error);
                continue;
            }
            if (status == PlainDecode::Declined) {
                ++declined;
            } else {
                ASSERT_TRUE(reference.has_value()) << "libtiff refuses what the plain reader decodes: " << refused;
                ASSERT_TRUE(fast == *reference) << trial;
                ++same;
            }
            try {
                const std::vector<int16_t> got = decodeResidualBlob(blob, size, "tile");
                ASSERT_TRUE(reference.has_value());
                EXPECT_TRUE(got == *reference);
            } catch (const Error& e) {
                EXPECT_EQ(std::string(e.what()), refused);
            }
        }
    }
    EXPECT_GT(declined + damaged, 100); // most damage is seen (the rest changes nothing libtiff reads)
    EXPECT_GT(damaged, 0);
    EXPECT_GT(same, 0);
}

// Damage libtiff alone would not see: it inflates a strip only until the strip is full, so a
// stream that runs long is never checked against its Adler-32 (damage that makes a stream run long
// leaves it so). The streams are inflated whole (formats/zlib_strip.hpp): such a tile is refused,
// in one line naming it, by the plain reader and by the libtiff one alike; a whole stream that
// runs long with its checksum right is read as libtiff reads it.
TEST(PlainResidualTiff, AStreamRunningLongFailingItsChecksumIsRefused) {
    const int size = 29;
    const std::vector<int16_t> r = residuals(size, 4);
    std::vector<uint8_t> bytes(r.size() * 2 + 1, 0x5a); // one byte more than the strip
    for (size_t k = 0; k < r.size(); ++k) {
        bytes[2 * k] = static_cast<uint8_t>(static_cast<uint16_t>(r[k]) & 0xff);
        bytes[2 * k + 1] = static_cast<uint8_t>(static_cast<uint16_t>(r[k]) >> 8);
    }
    const std::span<const uint8_t> z = zlibCompress(bytes, 6);
    std::vector<uint8_t> stream(z.begin(), z.end());
    PlainTiffShape shape;
    shape.width = shape.height = size;
    shape.channels = 2;
    const std::vector<uint8_t> longer = writePlainTiff(stream, shape);
    std::vector<int16_t> out(r.size());
    EXPECT_EQ(decodePlainResidualTiff(longer, size, out), PlainDecode::Declined);
    EXPECT_TRUE(decodeResidualTiff(longer, size, "t") == r);
    EXPECT_TRUE(decodeResidualBlob(longer, size, "t") == r);

    stream.back() ^= 0x01; // the Adler-32's last byte
    const std::vector<uint8_t> damaged = writePlainTiff(stream, shape);
    EXPECT_EQ(decodePlainResidualTiff(damaged, size, out), PlainDecode::Damaged);
    for (const bool plainFirst : {true, false}) {
        try {
            if (plainFirst) {
                decodeResidualBlob(damaged, size, "DEM.dat: tile (3,1,2)");
            } else {
                decodeResidualTiff(damaged, size, "DEM.dat: tile (3,1,2)");
            }
            FAIL() << "a tile failing its checksum decoded";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("DEM.dat: tile (3,1,2): truncated or corrupt TIFF data"), std::string::npos) << what;
            EXPECT_NE(what.find("checksum"), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    }
}

} // namespace
} // namespace pyramid
