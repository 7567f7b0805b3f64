// The TIFF tiles written without libtiff (formats/tiff_plain_writer.hpp) are libtiff's bytes:
// for every shape libpyramid writes (residual tiles of 2 x 8 and 1 x 16 bits, image tiles of 1 to
// 4 channels, with and without the predictor), libtiff writes the same tags around the same
// strip, and the two files must be equal; libtiff reads every tile back to its samples.
#include <gtest/gtest.h>

#include <tiffio.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/residual_tiff_plain.hpp"
#include "formats/tiff_plain_writer.hpp"
#include "formats/tiff_tile.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
    return b[at] | b[at + 1] << 8 | b[at + 2] << 16 | static_cast<uint32_t>(b[at + 3]) << 24;
}

// The file libtiff writes with `shape`'s tags around `blob`'s strip (its bytes at 8, as many as
// the directory's StripByteCounts, the tenth entry, says).
std::string libtiffFile(const std::string& path, const std::vector<uint8_t>& blob, const PlainTiffShape& shape) {
    EXPECT_GT(blob.size(), 8u + 2 + 12 * 10);
    const uint32_t stripBytes = u32(blob, u32(blob, 4) + 2 + 12 * 9 + 8);
    TIFF* t = TIFFOpen(path.c_str(), "wl");
    EXPECT_NE(t, nullptr);
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(shape.width));
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(shape.height));
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, static_cast<uint16_t>(shape.bits));
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, static_cast<uint16_t>(shape.channels));
    TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, shape.photometric);
    TIFFSetField(t, TIFFTAG_ORIENTATION, ORIENTATION_BOTLEFT);
    TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, static_cast<uint32_t>(shape.height));
    TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
    if (shape.bits == 16) {
        TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_INT);
    }
    if (shape.extraSample) {
        const uint16_t extra = EXTRASAMPLE_UNSPECIFIED;
        TIFFSetField(t, TIFFTAG_EXTRASAMPLES, 1, &extra);
    }
    if (shape.predictor) {
        TIFFSetField(t, TIFFTAG_PREDICTOR, PREDICTOR_HORIZONTAL);
    }
    EXPECT_EQ(TIFFWriteRawStrip(t, 0, const_cast<uint8_t*>(&blob[8]), stripBytes), static_cast<tmsize_t>(stripBytes));
    TIFFClose(t);
    return test::readFile(path);
}

TEST(PlainTiffWriter, ResidualTilesAreTheBytesLibtiffWrites) {
    test::TempDir dir;
    std::mt19937 rng(3);
    int compared = 0;
    for (const int size : {1, 2, 5, 30, 197}) {
        std::vector<int16_t> r(static_cast<size_t>(size) * static_cast<size_t>(size));
        for (int16_t& v : r) {
            v = static_cast<int16_t>(static_cast<int>(rng() % 601) - 300 + (rng() % 9 == 0 ? 9000 : 0));
        }
        for (const auto layout : {ResidualTiffLayout::TwoBytes, ResidualTiffLayout::OneShort}) {
            for (const bool predictor : {false, true}) {
                for (const int level : {1, 2, 12}) {
                    const std::vector<uint8_t> blob = encodeResidualTiff(r, size, level, layout, predictor);
                    ASSERT_TRUE(decodeResidualTiff(blob, size, "t") == r) << size << " " << predictor << " " << level;
                    const bool oneShort = layout == ResidualTiffLayout::OneShort;
                    const PlainTiffShape shape{size, size, oneShort ? 1 : 2, oneShort ? 16 : 8, PHOTOMETRIC_MINISBLACK,
                                               false, predictor};
                    ASSERT_EQ(std::string(blob.begin(), blob.end()), libtiffFile(dir.file("r.tif"), blob, shape))
                        << size << " " << oneShort << " " << predictor;
                    ++compared;
                }
            }
        }
    }
    EXPECT_EQ(compared, 60);
}

TEST(PlainTiffWriter, ImageTilesAreTheBytesLibtiffWrites) {
    test::TempDir dir;
    std::mt19937 rng(4);
    int compared = 0;
    for (const auto& [width, height] : {std::pair{1, 1}, std::pair{7, 3}, std::pair{64, 64}, std::pair{197, 197}}) {
        for (int channels = 1; channels <= 4; ++channels) {
            std::vector<uint8_t> pixels(static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(channels));
            for (size_t k = 0; k < pixels.size(); ++k) {
                pixels[k] = static_cast<uint8_t>(k % 5 == 0 ? rng() : k / 7); // repeats and noise
            }
            for (const bool predictor : {false, true}) {
                const std::vector<uint8_t> blob =
                    encodeTiff8(pixels, width, height, channels, TiffCompression::Deflate, 90, 2, predictor);
                const TiffImage back = decodeTiff(blob, width, height, "t");
                ASSERT_TRUE(back.pixels == pixels) << width << " " << channels << " " << predictor;
                const PlainTiffShape shape{width, height, channels, 8,
                                           static_cast<uint16_t>(channels >= 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK),
                                           channels == 2 || channels == 4, predictor};
                ASSERT_EQ(std::string(blob.begin(), blob.end()), libtiffFile(dir.file("i.tif"), blob, shape))
                    << width << "x" << height << " " << channels << " " << predictor;
                ++compared;
            }
        }
    }
    EXPECT_EQ(compared, 32);
}

TEST(PlainTiffWriter, RefusesWhatIsNotAPlainTile) {
    const std::vector<uint8_t> stream(12, 0);
    EXPECT_THROW(writePlainTiff(stream, {70000, 4, 1, 8, 1, false, false}), Error);
    EXPECT_THROW(writePlainTiff(stream, {4, 4, 5, 8, 1, false, false}), Error);
    EXPECT_THROW(writePlainTiff(stream, {4, 4, 2, 16, 1, false, false}), Error);
    EXPECT_NO_THROW(writePlainTiff(stream, {65535, 1, 1, 16, 1, false, false}));
    // Deflate levels beyond libdeflate's 1 to 12, whichever tile.
    const std::vector<int16_t> residuals(25, 3);
    const std::vector<uint8_t> pixels(25 * 3, 7);
    for (const int level : {0, 13}) {
        EXPECT_THROW(encodeResidualTiff(residuals, 5, level), Error) << level;
        EXPECT_THROW(encodeTiff8(pixels, 5, 5, 3, TiffCompression::Deflate, 90, level), Error) << level;
    }
    EXPECT_NO_THROW(encodeTiff8(pixels, 5, 5, 3, TiffCompression::Deflate, 90, 12));
}

} // namespace
} // namespace pyramid
