// Compressed TIFFs decoded without the image I/O module, with the same samples as OpenImageIO's:
// blocks libtiff decodes itself, read block by block (JPEG: grey, RGB, YCbCr; WebP: imagery COGs,
// lossless or lossy; LERC: elevation COGs, within their stored error). Damaged JPEG data is
// refused with one line naming the file and the block. (JPEG files: raster_readers_jpeg_test.cpp.)
#include <gtest/gtest.h>

#include <tiffio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/input/tiff_block_reader.hpp"
#include "tests/support/oiio_reference.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/tiff_writing.hpp"

namespace pyramid {
namespace {

using test::expectSameAsOpenImageIO;

// A JPEG-compressed TIFF written with libtiff: 8-bit grey, RGB or YCbCr (2 x 2 chroma
// subsampling, given as RGB and converted by libjpeg), in strips of `rows` or tiles of `tile`.
void writeJpegTiff(const std::string& path, int w, int h, int channels, bool ycbcr, int tile, int rows) {
    TIFF* tif = TIFFOpen(path.c_str(), "w");
    ASSERT_TRUE(tif);
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, w);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, h);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, channels);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 8);
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_JPEG);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC,
                 channels == 1 ? PHOTOMETRIC_MINISBLACK : ycbcr ? PHOTOMETRIC_YCBCR : PHOTOMETRIC_RGB);
    if (ycbcr) {
        TIFFSetField(tif, TIFFTAG_YCBCRSUBSAMPLING, 2, 2);
        TIFFSetField(tif, TIFFTAG_JPEGCOLORMODE, JPEGCOLORMODE_RGB);
    }
    if (channels == 4) {
        const uint16_t alpha = EXTRASAMPLE_UNASSALPHA;
        TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, 1, &alpha);
    }
    TIFFSetField(tif, TIFFTAG_JPEGQUALITY, 75);
    const auto value = [&](int x, int y, int c) {
        // Smooth colours with some detail, as photographs have.
        return static_cast<uint8_t>((x * (3 + c) + y * (5 - c) + ((x * y + 7 * c) % 23) * 3) & 255);
    };
    if (tile) {
        TIFFSetField(tif, TIFFTAG_TILEWIDTH, tile);
        TIFFSetField(tif, TIFFTAG_TILELENGTH, tile);
        std::vector<uint8_t> block(static_cast<size_t>(tile * tile * channels));
        for (int ty = 0; ty < h; ty += tile) {
            for (int tx = 0; tx < w; tx += tile) {
                for (int y = 0; y < tile; ++y) {
                    for (int x = 0; x < tile; ++x) {
                        for (int c = 0; c < channels; ++c) {
                            block[static_cast<size_t>((y * tile + x) * channels + c)] =
                                value(std::min(tx + x, w - 1), std::min(ty + y, h - 1), c);
                        }
                    }
                }
                ASSERT_GE(TIFFWriteTile(tif, block.data(), static_cast<uint32_t>(tx), static_cast<uint32_t>(ty), 0, 0),
                          0);
            }
        }
    } else {
        TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, rows);
        for (int s = 0; s * rows < h; ++s) {
            const int n = std::min(rows, h - s * rows);
            std::vector<uint8_t> strip(static_cast<size_t>(n * w * channels));
            for (int y = 0; y < n; ++y) {
                for (int x = 0; x < w; ++x) {
                    for (int c = 0; c < channels; ++c) {
                        strip[static_cast<size_t>((y * w + x) * channels + c)] = value(x, s * rows + y, c);
                    }
                }
            }
            ASSERT_GE(TIFFWriteEncodedStrip(tif, static_cast<uint32_t>(s), strip.data(),
                                            static_cast<tmsize_t>(strip.size())),
                      0);
        }
    }
    TIFFClose(tif);
}

// JPEG-compressed TIFFs are decoded by libtiff and libjpeg block by block (YCbCr converted to
// RGB by libjpeg), the same samples as OpenImageIO's, without the module: tiles, strips, one
// strip beyond the cache (decoded once, row by row), grey, RGB and YCbCr.
TEST(RasterReaders, JpegTiffsAreReadBlockByBlockAsOpenImageIOReadsThem) {
    test::TempDir dir;
    struct Jpeg {
        std::string name;
        int w, h, channels;
        bool ycbcr;
        int tile, rows, cacheMegabytes;
    };
    for (const Jpeg& j : std::vector<Jpeg>{{"ycbcr-tiled.tif", 61, 37, 3, true, 16, 0, 256},
                                           {"ycbcr-strips.tif", 61, 37, 3, true, 0, 16, 256},
                                           {"rgb-strips.tif", 61, 37, 3, false, 0, 8, 256},
                                           {"grey-tiled.tif", 61, 37, 1, false, 32, 0, 256},
                                           {"ycbcr-one-strip.tif", 400, 300, 3, true, 0, 300, 1}}) {
        const std::string path = dir.file(j.name);
        writeJpegTiff(path, j.w, j.h, j.channels, j.ycbcr, j.tile, j.rows);
        const RasterInfo info = RasterSource::describe(path);
        EXPECT_EQ(info.channels, j.channels) << j.name;
        EXPECT_NE(TiffBlockReader::open(path, info, j.cacheMegabytes), nullptr) << j.name;
        expectSameAsOpenImageIO(path, j.cacheMegabytes);

        // Its second block's entropy-coded data damaged: libjpeg decodes on, with a warning,
        // which the reader makes an error naming the file and the block.
        TIFF* tif = TIFFOpen(path.c_str(), "r");
        ASSERT_TRUE(tif);
        const uint32_t block = TIFFNumberOfStrips(tif) > 1 || TIFFIsTiled(tif) ? 1 : 0;
        const uint64_t offset = TIFFGetStrileOffset(tif, block), count = TIFFGetStrileByteCount(tif, block);
        TIFFClose(tif);
        std::string bytes = test::readFile(path);
        for (uint64_t k = offset + count / 2; k < offset + count / 2 + 12; ++k) {
            bytes[static_cast<size_t>(k)] = static_cast<char>(k % 2 ? 0xFF : 0x00);
        }
        const std::string damaged = dir.file("damaged-" + j.name);
        std::ofstream(damaged, std::ios::binary) << bytes;
        const auto source = RasterSource::open(damaged, j.cacheMegabytes);
        std::vector<uint8_t> pixels(static_cast<size_t>(j.w * j.h * j.channels));
        try {
            source->readUInt8(0, 0, j.w, j.h, 0, j.channels, pixels.data(), j.w * j.channels);
            ADD_FAILURE() << "damaged " << j.name << " was read";
        } catch (const Error& e) {
            const std::string where = j.tile ? "tile 1" : block ? "strip 1" : "its strips";
            EXPECT_EQ(std::string(e.what()).rfind(damaged + ": damaged JPEG data in " + where + ": ", 0), 0u)
                << e.what();
        }
    }
}

// RGBA JPEG (unassociated alpha): the colours as stored, as libtiff decodes them, not multiplied
// by alpha (which OpenImageIO does for these files whatever its unassociated-alpha setting).
TEST(RasterReaders, RgbaJpegTiffsGiveTheirStoredColours) {
    test::TempDir dir;
    const std::string path = dir.file("rgba.tif");
    const int w = 40, h = 24;
    writeJpegTiff(path, w, h, 4, false, 16, 0);
    TIFF* tif = TIFFOpen(path.c_str(), "r");
    ASSERT_TRUE(tif);
    std::vector<uint8_t> expected(static_cast<size_t>(w * h * 4)), block(static_cast<size_t>(TIFFTileSize(tif)));
    for (int ty = 0; ty < h; ty += 16) {
        for (int tx = 0; tx < w; tx += 16) {
            ASSERT_GE(TIFFReadTile(tif, block.data(), static_cast<uint32_t>(tx), static_cast<uint32_t>(ty), 0, 0), 0);
            for (int y = ty; y < std::min(h, ty + 16); ++y) {
                for (int x = tx; x < std::min(w, tx + 16); ++x) {
                    std::copy_n(&block[static_cast<size_t>(((y - ty) * 16 + (x - tx)) * 4)], 4,
                                &expected[static_cast<size_t>((y * w + x) * 4)]);
                }
            }
        }
    }
    TIFFClose(tif);
    std::vector<uint8_t> got(expected.size());
    RasterSource::open(path)->readUInt8(0, 0, w, h, 0, 4, got.data(), w * 4);
    EXPECT_EQ(got, expected);
    // The alpha of this pattern is not all opaque: multiplied colours would differ.
    EXPECT_NE(*std::min_element(expected.begin(), expected.end()), 255);
}

// A WebP or LERC TIFF written with libtiff, tiled or in strips: `channels` interleaved samples
// of 8 bits (WebP: RGB or RGBA) or of `bits` bits of `format` (LERC), smooth values with detail,
// as a photograph or a DEM has. WebP lossless or at quality 75; LERC within `maxError`.
struct CodecTiff {
    std::string name;
    uint16_t compression;
    int channels;
    uint16_t bits, format;
    double maxError; // LERC; WebP: 0 lossless, else lossy
    int tile, rows;
    int w = 61, h = 37, cacheMegabytes = 256;
};

double codecValue(const CodecTiff& c, int x, int y, int ch) {
    const double smooth = (x * (3 + ch) + y * (5 - ch)) % 200 + ((x * y + 7 * ch) % 23) * 2;
    if (c.format == SAMPLEFORMAT_IEEEFP) {
        return smooth * 7.25 - 300.0;
    }
    return c.bits == 8 ? smooth : smooth * 13 - (c.format == SAMPLEFORMAT_INT ? 1000 : 0);
}

void writeCodecTiff(const std::string& path, const CodecTiff& c, int w, int h) {
    TIFF* tif = test::createTiff(path, {w, h, c.channels, c.bits, c.format, PLANARCONFIG_CONTIG, 0, c.compression});
    ASSERT_TRUE(tif);
    if (c.compression == COMPRESSION_WEBP) {
        TIFFSetField(tif, TIFFTAG_WEBP_LOSSLESS, c.maxError == 0 ? 1 : 0);
        TIFFSetField(tif, TIFFTAG_WEBP_LEVEL, 75);
    } else {
        TIFFSetField(tif, TIFFTAG_LERC_MAXZERROR, c.maxError);
    }
    const size_t sampleBytes = c.bits / 8u;
    const auto put = [&](int x, int y, uint8_t* to) {
        for (int ch = 0; ch < c.channels; ++ch) {
            const double v = codecValue(c, x, y, ch);
            uint8_t* s = to + static_cast<size_t>(ch) * sampleBytes;
            if (c.format == SAMPLEFORMAT_IEEEFP) {
                const auto f = static_cast<float>(v);
                std::memcpy(s, &f, 4);
            } else if (c.bits == 8) {
                *s = static_cast<uint8_t>(v);
            } else {
                const auto i = static_cast<int16_t>(v);
                std::memcpy(s, &i, 2);
            }
        }
    };
    const size_t pixelBytes = sampleBytes * static_cast<size_t>(c.channels);
    if (c.tile) {
        TIFFSetField(tif, TIFFTAG_TILEWIDTH, c.tile);
        TIFFSetField(tif, TIFFTAG_TILELENGTH, c.tile);
        std::vector<uint8_t> block(static_cast<size_t>(c.tile * c.tile) * pixelBytes);
        for (int ty = 0; ty < h; ty += c.tile) {
            for (int tx = 0; tx < w; tx += c.tile) {
                for (int y = 0; y < c.tile; ++y) {
                    for (int x = 0; x < c.tile; ++x) {
                        put(std::min(tx + x, w - 1), std::min(ty + y, h - 1),
                            &block[static_cast<size_t>(y * c.tile + x) * pixelBytes]);
                    }
                }
                ASSERT_GE(TIFFWriteTile(tif, block.data(), static_cast<uint32_t>(tx), static_cast<uint32_t>(ty), 0, 0), 0);
            }
        }
    } else {
        TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, c.rows);
        for (int s = 0; s * c.rows < h; ++s) {
            const int n = std::min(c.rows, h - s * c.rows);
            std::vector<uint8_t> strip(static_cast<size_t>(n * w) * pixelBytes);
            for (int y = 0; y < n; ++y) {
                for (int x = 0; x < w; ++x) {
                    put(x, s * c.rows + y, &strip[static_cast<size_t>(y * w + x) * pixelBytes]);
                }
            }
            ASSERT_GE(TIFFWriteEncodedStrip(tif, static_cast<uint32_t>(s), strip.data(), static_cast<tmsize_t>(strip.size())), 0);
        }
    }
    TIFFClose(tif);
}

// WebP and LERC TIFFs are decoded by libtiff block by block, without the module, with
// OpenImageIO's samples; lossless WebP and LERC give the written values, lossy LERC stays
// within its stored error.
TEST(RasterReaders, WebpAndLercTiffsAreReadBlockByBlockAsOpenImageIOReadsThem) {
    test::TempDir dir;
    const std::vector<CodecTiff> cases = {
        {"webp-lossless-rgb-tiled.tif", COMPRESSION_WEBP, 3, 8, SAMPLEFORMAT_UINT, 0, 32, 0},
        {"webp-lossy-rgba-strips.tif", COMPRESSION_WEBP, 4, 8, SAMPLEFORMAT_UINT, 1, 0, 16},
        {"lerc-f32-tiled.tif", COMPRESSION_LERC, 1, 32, SAMPLEFORMAT_IEEEFP, 0.5, 32, 0},
        {"lerc-i16-strips.tif", COMPRESSION_LERC, 1, 16, SAMPLEFORMAT_INT, 0, 0, 16},
        {"lerc-rgb8-strips.tif", COMPRESSION_LERC, 3, 8, SAMPLEFORMAT_UINT, 0, 0, 8},
        // One strip beyond a quarter of the cache: decoded once, row by row, into the scratch file.
        {"lerc-f32-one-strip.tif", COMPRESSION_LERC, 1, 32, SAMPLEFORMAT_IEEEFP, 0, 0, 300, 400, 300, 1},
        {"webp-lossless-rgb-one-strip.tif", COMPRESSION_WEBP, 3, 8, SAMPLEFORMAT_UINT, 0, 0, 300, 400, 300, 1},
    };
    for (const CodecTiff& c : cases) {
        const int w = c.w, h = c.h;
        if (!TIFFIsCODECConfigured(c.compression)) {
            continue; // a libtiff built without WebP or LERC
        }
        SCOPED_TRACE(c.name);
        const std::string path = dir.file(c.name);
        writeCodecTiff(path, c, w, h);
        const RasterInfo info = RasterSource::describe(path);
        EXPECT_EQ(info.channels, c.channels);
        EXPECT_NE(TiffBlockReader::open(path, info, c.cacheMegabytes), nullptr);
        expectSameAsOpenImageIO(path, c.cacheMegabytes);
        const bool lossy = c.compression == COMPRESSION_WEBP ? c.maxError != 0 : false;
        if (lossy) {
            continue;
        }
        const auto source = RasterSource::open(path, c.cacheMegabytes);
        std::vector<float> got(static_cast<size_t>(w * h));
        for (int ch = 0; ch < c.channels; ++ch) {
            source->readFloat(0, 0, w, h, ch, got.data());
            double worst = 0;
            for (int y = 0; y < h; ++y) {
                for (int x = 0; x < w; ++x) {
                    const double want = static_cast<float>(codecValue(c, x, y, ch));
                    worst = std::max(worst, std::abs(got[static_cast<size_t>(y * w + x)] - want));
                }
            }
            EXPECT_LE(worst, c.maxError) << "channel " << ch;
        }
    }
}

} // namespace
} // namespace pyramid
