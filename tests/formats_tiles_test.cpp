// Tile codecs on their own: the TIFF tags the original readers rely on, strip order, the
// compression a blob reports, JPEG quality, and the DXT quality levels against libsquish.
#include <gtest/gtest.h>
#include <squish.h>
#include <tiffio.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"
#include "formats/residual_tiff_plain.hpp"
#include "formats/tiff_tile.hpp"
#include "tests/support/dxt_blocks.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

// The tags of a blob, read with plain libtiff from a file (independently of formats/).
struct Tags {
    uint32_t width = 0, height = 0, rowsPerStrip = 0;
    uint16_t bits = 0, samples = 0, compression = 0, photometric = 0, orientation = 0, extraCount = 0;
    uint32_t strips = 0;
};

Tags tagsOf(const std::vector<uint8_t>& blob) {
    test::TempDir dir;
    const std::string path = dir.file("tile.tif");
    FILE* f = std::fopen(path.c_str(), "wb");
    EXPECT_NE(f, nullptr);
    EXPECT_EQ(std::fwrite(blob.data(), 1, blob.size(), f), blob.size());
    std::fclose(f);
    Tags tags;
    TIFF* t = TIFFOpen(path.c_str(), "r");
    EXPECT_NE(t, nullptr);
    TIFFGetField(t, TIFFTAG_IMAGEWIDTH, &tags.width);
    TIFFGetField(t, TIFFTAG_IMAGELENGTH, &tags.height);
    TIFFGetField(t, TIFFTAG_ROWSPERSTRIP, &tags.rowsPerStrip);
    TIFFGetField(t, TIFFTAG_BITSPERSAMPLE, &tags.bits);
    TIFFGetField(t, TIFFTAG_SAMPLESPERPIXEL, &tags.samples);
    TIFFGetField(t, TIFFTAG_COMPRESSION, &tags.compression);
    TIFFGetField(t, TIFFTAG_PHOTOMETRIC, &tags.photometric);
    TIFFGetField(t, TIFFTAG_ORIENTATION, &tags.orientation);
    uint16_t* extra = nullptr;
    if (!TIFFGetField(t, TIFFTAG_EXTRASAMPLES, &tags.extraCount, &extra)) {
        tags.extraCount = 0;
    }
    tags.strips = TIFFNumberOfStrips(t);
    TIFFClose(t);
    return tags;
}

std::vector<uint8_t> gradient(int size, int channels) {
    std::vector<uint8_t> v(static_cast<size_t>(size) * size * channels);
    for (size_t k = 0; k < v.size(); ++k) {
        v[k] = static_cast<uint8_t>((k * 7 + (k / channels / size) * 3) & 0xff);
    }
    return v;
}

// A tile blob as plain libtiff sees it from a file (the way another reader would open it). The
// caller closes the handle; null if libtiff cannot open it.
TIFF* openWithLibtiff(const std::vector<uint8_t>& blob, const test::TempDir& dir) {
    const std::string path = dir.file("tile.tif");
    FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        return nullptr;
    }
    const bool written = std::fwrite(blob.data(), 1, blob.size(), f) == blob.size();
    std::fclose(f);
    return written ? TIFFOpen(path.c_str(), "r") : nullptr;
}

int largestDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    int worst = 0;
    for (size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
        worst = std::max(worst, std::abs(static_cast<int>(a[k]) - static_cast<int>(b[k])));
    }
    return worst;
}

TEST(ResidualTiff, WrittenAsTheOriginalToolsWriteThem) {
    const int size = 13;
    std::vector<int16_t> residuals(size * size);
    for (size_t k = 0; k < residuals.size(); ++k) {
        residuals[k] = static_cast<int16_t>(static_cast<int>(k) * 397 - 30000);
    }
    const auto blob = encodeResidualTiff(residuals, size);
    const Tags tags = tagsOf(blob);
    EXPECT_EQ(tags.width, 13u);
    EXPECT_EQ(tags.height, 13u);
    EXPECT_EQ(tags.samples, 2);                           // low byte, high byte
    EXPECT_EQ(tags.bits, 8);
    EXPECT_EQ(tags.extraCount, 0);                        // no ExtraSamples tag
    EXPECT_EQ(tags.compression, COMPRESSION_ADOBE_DEFLATE); // code 8
    EXPECT_EQ(tags.photometric, PHOTOMETRIC_MINISBLACK);
    EXPECT_EQ(tags.orientation, ORIENTATION_BOTLEFT);
    EXPECT_EQ(tags.strips, 1u);
    EXPECT_EQ(tags.rowsPerStrip, 13u);
    EXPECT_EQ(describeTiff(blob), "deflate");

    // Strip byte order: sample k is bytes 2k (low) and 2k+1 (high), row 0 first.
    const TiffImage image = decodeTiff(blob, size, size, "t");
    ASSERT_EQ(image.pixels.size(), residuals.size() * 2);
    for (size_t k : {size_t{0}, size_t{1}, size_t{13}, residuals.size() - 1}) {
        const auto v = static_cast<uint16_t>(residuals[k]);
        EXPECT_EQ(image.pixels[2 * k], v & 0xff) << k;
        EXPECT_EQ(image.pixels[2 * k + 1], v >> 8) << k;
    }
    EXPECT_EQ(decodeResidualTiff(blob, size, "t"), residuals);
}

TEST(ResidualTiff, WrongSizeIsAnErrorNamingTheTile) {
    const auto blob = encodeResidualTiff(std::vector<int16_t>(9 * 9, 5), 9);
    try {
        decodeResidualTiff(blob, 13, "DEM.dat: tile (1,0,0)");
        ADD_FAILURE() << "a 9x9 tile was accepted as 13x13";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "DEM.dat: tile (1,0,0): residual tile of 9x9 samples, expected 13x13");
    }
    EXPECT_THROW(decodeResidualTiff(blob, 7, "t"), Error); // larger than allowed: refused before decoding
}

TEST(OrthoTiff, TagsAndCompressionNames) {
    struct Case {
        int channels;
        TiffCompression compression;
        const char* name;
        uint16_t photometric;
        uint16_t extra;
    };
    for (const Case& c : {Case{1, TiffCompression::None, "none", PHOTOMETRIC_MINISBLACK, 0},
                          Case{2, TiffCompression::Lzw, "lzw", PHOTOMETRIC_MINISBLACK, 1},
                          Case{3, TiffCompression::Jpeg, "jpeg", PHOTOMETRIC_RGB, 0},
                          Case{4, TiffCompression::Deflate, "deflate", PHOTOMETRIC_RGB, 1}}) {
        SCOPED_TRACE(c.name);
        const auto pixels = gradient(16, c.channels);
        const auto blob = encodeTiff8(pixels, 16, 16, c.channels, c.compression, 90);
        const Tags tags = tagsOf(blob);
        EXPECT_EQ(describeTiff(blob), c.name);
        EXPECT_EQ(tags.samples, c.channels);
        EXPECT_EQ(tags.bits, 8);
        EXPECT_EQ(tags.photometric, c.photometric);
        EXPECT_EQ(tags.orientation, ORIENTATION_BOTLEFT);
        EXPECT_EQ(tags.extraCount, c.extra);
        EXPECT_EQ(tags.strips, 1u);
        const auto decoded = decodeOrthoTiff(blob, 16, c.channels, "t");
        if (c.compression != TiffCompression::Jpeg) {
            EXPECT_EQ(decoded, pixels);
        }
        EXPECT_THROW(decodeOrthoTiff(blob, 16, c.channels == 4 ? 3 : c.channels + 1, "t"), Error);
    }
    EXPECT_EQ(describeTiff(std::vector<uint8_t>{1, 2, 3}), "invalid");
}

// Deflate tiles with the horizontal predictor (what preprocessOrtho writes): the Predictor tag
// is set and plain libtiff, reading the strip as the original runtime does (TIFFReadEncodedStrip,
// no other setting), returns the very pixels that were encoded, for every channel count and
// Deflate level.
TEST(OrthoTiff, PredictorTilesDecodeToTheSamePixelsWithPlainLibtiff) {
    for (int channels = 1; channels <= 4; ++channels) {
        for (int level : {1, 6, 12}) {
            SCOPED_TRACE(std::to_string(channels) + " channels, level " + std::to_string(level));
            const auto pixels = gradient(20, channels);
            const auto blob = encodeTiff8(pixels, 20, 20, channels, TiffCompression::Deflate, 90, level, true);
            EXPECT_EQ(describeTiff(blob), "deflate");
            EXPECT_EQ(decodeOrthoTiff(blob, 20, channels, "t"), pixels);
            test::TempDir dir;
            TIFF* t = openWithLibtiff(blob, dir);
            ASSERT_NE(t, nullptr);
            uint16_t predictor = 0;
            TIFFGetField(t, TIFFTAG_PREDICTOR, &predictor);
            EXPECT_EQ(predictor, PREDICTOR_HORIZONTAL);
            std::vector<uint8_t> strip(pixels.size());
            EXPECT_EQ(TIFFReadEncodedStrip(t, 0, strip.data(), static_cast<tmsize_t>(strip.size())),
                      static_cast<tmsize_t>(strip.size()));
            TIFFClose(t);
            EXPECT_EQ(strip, pixels);
        }
    }
    // Without the predictor (the default, as residual and DEM tiles are written) nothing changes.
    const auto plain = encodeTiff8(gradient(20, 3), 20, 20, 3, TiffCompression::Deflate, 90);
    EXPECT_EQ(decodeOrthoTiff(plain, 20, 3, "t"), gradient(20, 3));
}

TEST(OrthoTiff, JpegQualityIsHonoured) {
    std::vector<uint8_t> pixels(64 * 64 * 3);
    for (size_t k = 0; k < pixels.size(); ++k) {
        pixels[k] = static_cast<uint8_t>((k * 2654435761u) >> 24); // detail JPEG must spend bits on
    }
    const auto low = encodeTiff8(pixels, 64, 64, 3, TiffCompression::Jpeg, 20);
    const auto high = encodeTiff8(pixels, 64, 64, 3, TiffCompression::Jpeg, 95);
    EXPECT_LT(low.size() * 2, high.size()) << low.size() << " vs " << high.size();
}

// YCbCr JPEG tiles: tagged as such (photometric YCbCr, 2 x 2 chroma subsampling), decoded to
// RGB close to the pixels by any libtiff reader that asks for RGB, and smaller than RGB JPEG at
// the same quality. Grey tiles have no chroma: the same bytes as plain JPEG.
TEST(OrthoTiff, YCbCrJpegTilesDecodeToRgb) {
    const int size = 64;
    std::vector<uint8_t> pixels(size * size * 3);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            uint8_t* p = &pixels[static_cast<size_t>((y * size + x) * 3)];
            p[0] = static_cast<uint8_t>(60 + 2 * x);
            p[1] = static_cast<uint8_t>(200 - 2 * y);
            p[2] = static_cast<uint8_t>(90 + x + y);
        }
    }
    const auto rgb = encodeTiff8(pixels, size, size, 3, TiffCompression::Jpeg, 90);
    const auto ycbcr = encodeTiff8(pixels, size, size, 3, TiffCompression::JpegYCbCr, 90);
    EXPECT_EQ(describeTiff(rgb), "jpeg");
    EXPECT_EQ(describeTiff(ycbcr), "jpeg-ycbcr");
    EXPECT_LT(ycbcr.size(), rgb.size());
    const auto back = decodeOrthoTiff(ycbcr, size, 3, "t");
    ASSERT_EQ(back.size(), pixels.size());
    EXPECT_LE(largestDifference(back, pixels), 6); // smooth colours: chroma subsampling loses little
    test::TempDir dir;
    TIFF* t = openWithLibtiff(ycbcr, dir);
    ASSERT_NE(t, nullptr);
    uint16_t photometric = 0, sx = 0, sy = 0;
    TIFFGetField(t, TIFFTAG_PHOTOMETRIC, &photometric);
    TIFFGetFieldDefaulted(t, TIFFTAG_YCBCRSUBSAMPLING, &sx, &sy);
    TIFFClose(t);
    EXPECT_EQ(photometric, PHOTOMETRIC_YCBCR);
    EXPECT_EQ(sx, 2);
    EXPECT_EQ(sy, 2);
    const std::vector<uint8_t> grey(size * size, 77);
    EXPECT_EQ(encodeTiff8(grey, size, size, 1, TiffCompression::JpegYCbCr, 90),
              encodeTiff8(grey, size, size, 1, TiffCompression::Jpeg, 90));
}

// The quantisation tables of JPEG tiles, read back from the blob: at quality 50 libjpeg uses the
// example tables of the JPEG standard (ITU T.81 Annex K, K.1 luminance and K.2 chrominance)
// unscaled. RGB tiles code every component with table 0 (no colour transform); YCbCr tiles
// code chroma with table 1. Other compressions have none; a cut blob is an error naming it.
TEST(OrthoTiff, JpegTablesAreReadFromTheTile) {
    // Natural (row-major) index of each zig-zag position, T.81 figure A.6.
    const int zigzag[64] = {0,  1,  8,  16, 9,  2,  3,  10, 17, 24, 32, 25, 18, 11, 4,  5,  12, 19, 26, 33, 40, 48,
                            41, 34, 27, 20, 13, 6,  7,  14, 21, 28, 35, 42, 49, 56, 57, 50, 43, 36, 29, 22, 15, 23,
                            30, 37, 44, 51, 58, 59, 52, 45, 38, 31, 39, 46, 53, 60, 61, 54, 47, 55, 62, 63};
    const int luminance[64] = {16, 11, 10, 16, 24,  40,  51,  61,  12, 12, 14, 19, 26,  58,  60,  55,
                               14, 13, 16, 24, 40,  57,  69,  56,  14, 17, 22, 29, 51,  87,  80,  62,
                               18, 22, 37, 56, 68,  109, 103, 77,  24, 35, 55, 64, 81,  104, 113, 92,
                               49, 64, 78, 87, 103, 121, 120, 101, 72, 92, 95, 98, 112, 100, 103, 99};
    int chrominance[64];
    for (int k = 0; k < 64; ++k) {
        const int row = k / 8, col = k % 8;
        const int top[4][4] = {{17, 18, 24, 47}, {18, 21, 26, 66}, {24, 26, 56, 99}, {47, 66, 99, 99}};
        chrominance[k] = row < 4 && col < 4 ? top[row][col] : 99;
    }
    const auto natural = [&](const std::array<uint16_t, 64>& table) {
        std::array<int, 64> out{};
        for (int k = 0; k < 64; ++k) {
            out[static_cast<size_t>(zigzag[k])] = table[static_cast<size_t>(k)];
        }
        return out;
    };
    const int size = 32;
    std::vector<uint8_t> pixels(size * size * 3);
    for (size_t k = 0; k < pixels.size(); ++k) {
        pixels[k] = static_cast<uint8_t>((k * 2654435761u) >> 24);
    }
    const auto rgb = jpegTileTables(encodeTiff8(pixels, size, size, 3, TiffCompression::Jpeg, 50), "t");
    ASSERT_TRUE(rgb.has_value());
    EXPECT_FALSE(rgb->ycbcr);
    ASSERT_EQ(rgb->components.size(), 3u);
    for (const auto& table : rgb->components) {
        const std::array<int, 64> n = natural(table);
        EXPECT_TRUE(std::equal(n.begin(), n.end(), luminance));
    }
    const auto ycbcr = jpegTileTables(encodeTiff8(pixels, size, size, 3, TiffCompression::JpegYCbCr, 50), "t");
    ASSERT_TRUE(ycbcr.has_value());
    EXPECT_TRUE(ycbcr->ycbcr);
    ASSERT_EQ(ycbcr->components.size(), 3u);
    const std::array<int, 64> y = natural(ycbcr->components[0]), cb = natural(ycbcr->components[1]);
    EXPECT_TRUE(std::equal(y.begin(), y.end(), luminance));
    EXPECT_TRUE(std::equal(cb.begin(), cb.end(), chrominance));
    // Quality 100 divides by 1 everywhere; quality 90 by a fifth of the example table, rounded.
    const auto best = jpegTileTables(encodeTiff8(pixels, size, size, 3, TiffCompression::Jpeg, 100), "t");
    ASSERT_TRUE(best.has_value());
    EXPECT_EQ(*std::max_element(best->components[0].begin(), best->components[0].end()), 1);
    const auto q90 = jpegTileTables(encodeTiff8(pixels, size, size, 3, TiffCompression::Jpeg, 90), "t");
    ASSERT_TRUE(q90.has_value());
    EXPECT_EQ(natural(q90->components[0])[63], (99 * 20 + 50) / 100);
    EXPECT_FALSE(jpegTileTables(encodeTiff8(pixels, size, size, 3, TiffCompression::Deflate), "t").has_value());
    const std::vector<uint8_t> grey(size * size, 7);
    const auto one = jpegTileTables(encodeTiff8(grey, size, size, 1, TiffCompression::Jpeg, 50), "t");
    ASSERT_TRUE(one.has_value());
    EXPECT_EQ(one->components.size(), 1u);
    // The blob cut inside its strip: an error naming the tile.
    std::vector<uint8_t> cut = encodeTiff8(pixels, size, size, 3, TiffCompression::Jpeg, 50);
    cut.resize(cut.size() / 2);
    try {
        jpegTileTables(cut, "tile (3,1,2)");
        ADD_FAILURE() << "a cut tile was read";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("tile (3,1,2)", 0), 0u) << e.what();
    }
}

// encodeDxt must hand each quality level to its encoder: its bytes equal direct per-block
// calls of the colour fit (levels 0 and 1: one and two refinements; DXT5 alpha blocks by
// stb_compress_bc4_block) and a direct
// squish::CompressImage call with the level's fit (levels 2 and 3), on the RGBA expansion of
// the pixels, for DXT1 and DXT5.
TEST(Dxt, QualityLevelsMapToTheirEncoders) {
    const int size = 8;
    for (const int channels : {3, 4}) {
        const auto pixels = gradient(size, channels);
        std::vector<uint8_t> rgba;
        for (size_t k = 0; k < pixels.size(); k += static_cast<size_t>(channels)) {
            rgba.insert(rgba.end(), {pixels[k], pixels[k + 1], pixels[k + 2],
                                     channels == 4 ? pixels[k + 3] : uint8_t{255}});
        }
        const DxtFormat format = channels == 4 ? DxtFormat::Dxt5 : DxtFormat::Dxt1;
        const size_t blockBytes = channels == 4 ? 16 : 8;
        std::vector<std::vector<uint8_t>> encoded;
        for (int quality = 0; quality < kDxtQualityLevels; ++quality) {
            std::vector<uint8_t> reference(dxtBytes(size, size, format));
            if (quality <= 1) {
                for (int by = 0; by < size; by += 4) {
                    for (int bx = 0; bx < size; bx += 4) {
                        uint8_t block[64];
                        for (int j = 0; j < 4; ++j) {
                            std::copy_n(&rgba[static_cast<size_t>(((by + j) * size + bx) * 4)], 16, block + 16 * j);
                        }
                        test::referenceDxtBlock(block, channels == 4, quality,
                                                &reference[((by / 4) * (size / 4) + bx / 4) * blockBytes]);
                    }
                }
            } else {
                const int fit = quality == 2 ? squish::kColourClusterFit : squish::kColourIterativeClusterFit;
                squish::CompressImage(rgba.data(), size, size, reference.data(),
                                      (channels == 4 ? squish::kDxt5 : squish::kDxt1) | fit);
            }
            encoded.push_back(encodeDxt(pixels, size, size, channels, format, quality));
            EXPECT_EQ(encoded.back(), reference) << channels << " channels, quality " << quality;
        }
        EXPECT_NE(encoded[0], encoded[2]); // the content tells the encoders apart
    }
}

// Partial blocks (an image not a multiple of 4 pixels across): every encoder fits the pixels
// inside the image only, and a smooth gradient decodes close to itself.
TEST(Dxt, PartialBlocksFitThePixelsInside) {
    const int w = 6, h = 5;
    std::vector<uint8_t> rgb;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            rgb.insert(rgb.end(), {static_cast<uint8_t>(40 + 6 * x), static_cast<uint8_t>(90 + 5 * y), 120});
        }
    }
    for (int quality = 0; quality < kDxtQualityLevels; ++quality) {
        const auto blob = encodeDxt(rgb, w, h, 3, DxtFormat::Dxt1, quality);
        ASSERT_EQ(blob.size(), 4u * 8u); // 2 x 2 blocks
        const auto back = decodeDxt(blob, w, h, DxtFormat::Dxt1, "t");
        ASSERT_EQ(back.size(), rgb.size());
        // A two-way gradient is no line in colour space: every encoder leaves some error here;
        // padding pulled into a fit costs more.
        EXPECT_LE(largestDifference(back, rgb), 12) << "quality " << quality;
    }
}

TEST(Dxt, GreyIsReplicatedAndAlphaKeptInDxt5) {
    const int size = 4;
    const std::vector<uint8_t> grey(size * size, 200);
    const auto rgb = decodeDxt(encodeDxt(grey, size, size, 1, DxtFormat::Dxt1), size, size, DxtFormat::Dxt1, "t");
    ASSERT_EQ(rgb.size(), 16u * 3u);
    for (uint8_t v : rgb) {
        EXPECT_NEAR(v, 200, 3); // R, G and B all carry the grey (RGB565 precision)
    }

    std::vector<uint8_t> rgbaIn;
    for (int k = 0; k < size * size; ++k) {
        rgbaIn.insert(rgbaIn.end(), {10, 20, 30, 255});
    }
    const auto rgba = decodeDxt(encodeDxt(rgbaIn, size, size, 4, DxtFormat::Dxt5), size, size, DxtFormat::Dxt5, "t");
    EXPECT_EQ(rgba.size(), 16u * 4u);
    EXPECT_EQ(rgba[3], 255);
    EXPECT_THROW(encodeDxt(rgbaIn, size, size, 4, DxtFormat::Dxt1), Error); // 4 channels need DXT5
    EXPECT_THROW(encodeDxt(grey, size, size, 1, DxtFormat::Dxt5), Error);
}

// The decoder is the library's own (the runtime links no libsquish): any block, including the
// three-colour DXT1 blocks and both DXT5 alpha modes, decodes to libsquish's pixels.
TEST(Dxt, DecodesEveryBlockAsLibsquishDoes) {
    std::mt19937 random(15);
    for (const DxtFormat format : {DxtFormat::Dxt1, DxtFormat::Dxt5}) {
        const size_t blockBytes = format == DxtFormat::Dxt1 ? 8u : 16u;
        const int blocks = 4096;
        std::vector<uint8_t> blob(blockBytes * blocks);
        for (auto& b : blob) {
            b = static_cast<uint8_t>(random());
        }
        // Equal endpoints too (the degenerate modes).
        blob[0] = blob[2];
        blob[1] = blob[3];
        const int width = 4 * 64, height = 4 * 64;
        const auto ours = decodeDxt(blob, width, height, format, "t");
        const int channels = format == DxtFormat::Dxt1 ? 3 : 4;
        const int flags = format == DxtFormat::Dxt1 ? squish::kDxt1 : squish::kDxt5;
        for (int k = 0; k < blocks; ++k) {
            uint8_t expected[64];
            squish::Decompress(expected, blob.data() + blockBytes * static_cast<size_t>(k), flags);
            const int bx = 4 * (k % 64), by = 4 * (k / 64);
            for (int p = 0; p < 16; ++p) {
                const size_t at = static_cast<size_t>((by + p / 4) * width + bx + p % 4) * static_cast<size_t>(channels);
                for (int c = 0; c < channels; ++c) {
                    ASSERT_EQ(ours[at + static_cast<size_t>(c)], expected[4 * p + c]) << "block " << k << " pixel " << p;
                }
            }
        }
    }
}

} // namespace
} // namespace pyramid
