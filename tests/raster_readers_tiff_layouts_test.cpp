// TIFF layouts whose blocks are not the samples as they stand, read block by block without the
// image I/O module, with the samples OpenImageIO gives: bands stored in separate planes (one
// chunk per band, interleaved as each block is decoded) and 8-bit palette indices (widened to
// their colours). Strips of such files too large for the cache are left to the module, with the
// same samples.
#include <gtest/gtest.h>

#include <tiffio.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
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

// A TIFF written with libtiff: `channels` bands of `bits`-bit samples (`format`), interleaved or
// in separate planes, or 8-bit palette indices (`palette`); in strips of `rows` or tiles of
// `tile`. Every sample differs from its neighbours and its bands.
struct TiffLayout {
    std::string name;
    int channels, bits;
    uint16_t format = SAMPLEFORMAT_UINT, planar = PLANARCONFIG_SEPARATE, compression = COMPRESSION_ADOBE_DEFLATE;
    int tile = 0, rows = 8;
    bool palette = false;
    uint16_t predictor = PREDICTOR_NONE;
};

// Sample c of pixel (x, y) of writeTiff's files: an integer below 251, or for floats a value
// that float32 holds exactly, or (float64) one it does not.
double valueAt(const TiffLayout& l, int x, int y, int c) {
    const int v = (x * 37 + y * 101 + c * 53 + x * y) % 251;
    if (l.format == SAMPLEFORMAT_IEEEFP) {
        return v * 1.25 - 77.5 + (l.bits == 64 ? (x + 1) / 3.0e6 : 0.0);
    }
    return l.bits == 16 ? v * 257 + c : v;
}

void writeTiff(const std::string& path, const TiffLayout& l, int w, int h) {
    TIFF* tif = test::createTiff(path, {w, h, l.channels, l.bits, l.format, l.planar,
                                        static_cast<uint16_t>(l.palette ? PHOTOMETRIC_PALETTE : 0), l.compression});
    ASSERT_TRUE(tif);
    std::vector<uint16_t> red(256), green(256), blue(256);
    if (l.palette) {
        // Entries that are not multiples of 257: divided by 257, rounded down, and their high
        // bytes are not always the same colours.
        for (int k = 0; k < 256; ++k) {
            red[k] = static_cast<uint16_t>(k * 251 + 7);
            green[k] = static_cast<uint16_t>(65535 - k * 199);
            blue[k] = static_cast<uint16_t>((k * 4099) % 65536);
        }
        TIFFSetField(tif, TIFFTAG_COLORMAP, red.data(), green.data(), blue.data());
    }
    if (l.tile) {
        TIFFSetField(tif, TIFFTAG_TILEWIDTH, l.tile);
        TIFFSetField(tif, TIFFTAG_TILELENGTH, l.tile);
    } else {
        TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, l.rows);
    }
    const int planes = l.planar == PLANARCONFIG_SEPARATE ? l.channels : 1;
    const int perPixel = l.channels / planes, sampleBytes = l.bits / 8;
    if (l.predictor != PREDICTOR_NONE) {
        TIFFSetField(tif, TIFFTAG_PREDICTOR, l.predictor);
    }
    // Sample c of pixel (x, y), as bytes of the file's type.
    const auto sample = [&](int x, int y, int c, uint8_t* to) {
        const double v = valueAt(l, x, y, c);
        if (l.bits == 64) {
            std::memcpy(to, &v, 8);
        } else if (l.format == SAMPLEFORMAT_IEEEFP) {
            const auto f = static_cast<float>(v);
            std::memcpy(to, &f, 4);
        } else if (l.bits == 16) {
            const auto u = static_cast<uint16_t>(v);
            std::memcpy(to, &u, 2);
        } else {
            *to = static_cast<uint8_t>(v);
        }
    };
    const int bw = l.tile ? l.tile : w, bh = l.tile ? l.tile : l.rows;
    std::vector<uint8_t> block(static_cast<size_t>(bw * bh * perPixel * sampleBytes));
    for (int p = 0; p < planes; ++p) {
        for (int by = 0; by < h; by += bh) {
            for (int bx = 0; bx < w; bx += bw) {
                const int rows = l.tile ? bh : std::min(bh, h - by);
                for (int y = 0; y < rows; ++y) {
                    for (int x = 0; x < bw; ++x) {
                        for (int c = 0; c < perPixel; ++c) {
                            uint8_t* to = block.data() + ((y * bw + x) * perPixel + c) * sampleBytes;
                            sample(std::min(bx + x, w - 1), std::min(by + y, h - 1), planes > 1 ? p : c, to);
                        }
                    }
                }
                const auto bytes = static_cast<tmsize_t>(rows * bw * perPixel * sampleBytes);
                const tmsize_t written =
                    l.tile ? TIFFWriteEncodedTile(tif, TIFFComputeTile(tif, bx, by, 0, static_cast<uint16_t>(p)),
                                                  block.data(), bytes)
                           : TIFFWriteEncodedStrip(tif, TIFFComputeStrip(tif, by, static_cast<uint16_t>(p)),
                                                   block.data(), bytes);
                ASSERT_EQ(written, bytes) << path;
            }
        }
    }
    TIFFClose(tif);
}

// Separate planes (8 and 16-bit, float32; tiled and striped, the last strip short; compressed or
// not) and palettes (tiled and striped) read block by block as OpenImageIO reads them.
TEST(RasterReaders, PlanesAndPalettesAreReadBlockByBlockAsOpenImageIOReadsThem) {
    test::TempDir dir;
    const std::vector<TiffLayout> layouts = {
        {"rgb8-planes-tiled.tif", 3, 8, SAMPLEFORMAT_UINT, PLANARCONFIG_SEPARATE, COMPRESSION_ADOBE_DEFLATE, 16},
        {"rgba8-planes-strips.tif", 4, 8, SAMPLEFORMAT_UINT, PLANARCONFIG_SEPARATE, COMPRESSION_LZW, 0, 8},
        {"rgb16-planes-none.tif", 3, 16, SAMPLEFORMAT_UINT, PLANARCONFIG_SEPARATE, COMPRESSION_NONE, 0, 5},
        {"greyalpha16-planes-tiled.tif", 2, 16, SAMPLEFORMAT_UINT, PLANARCONFIG_SEPARATE, COMPRESSION_ADOBE_DEFLATE,
         32},
        {"f32x2-planes.tif", 2, 32, SAMPLEFORMAT_IEEEFP, PLANARCONFIG_SEPARATE, COMPRESSION_ADOBE_DEFLATE, 0, 7},
        {"palette-tiled.tif", 1, 8, SAMPLEFORMAT_UINT, PLANARCONFIG_CONTIG, COMPRESSION_ADOBE_DEFLATE, 16, 0, true},
        {"palette-strips.tif", 1, 8, SAMPLEFORMAT_UINT, PLANARCONFIG_CONTIG, COMPRESSION_NONE, 0, 6, true},
    };
    for (const TiffLayout& l : layouts) {
        SCOPED_TRACE(l.name);
        const std::string path = dir.file(l.name);
        writeTiff(path, l, 61, 37);
        const RasterInfo info = RasterSource::describe(path);
        EXPECT_EQ(info.channels, l.palette ? 3 : l.channels);
        EXPECT_NE(TiffBlockReader::open(path, info, 256), nullptr);
        expectSameAsOpenImageIO(path);
    }
}

// Strips of planes or palette indices larger than a quarter of the cache are not decoded here
// (a block would need every plane's strip at once): the module reads them, with the same
// samples.
TEST(RasterReaders, HugeStripsOfPlanesAndPalettesAreLeftToTheModule) {
    test::TempDir dir;
    for (const TiffLayout& l : {TiffLayout{"planes-one-strip.tif", 3, 8, SAMPLEFORMAT_UINT, PLANARCONFIG_SEPARATE,
                                           COMPRESSION_ADOBE_DEFLATE, 0, 700},
                                TiffLayout{"palette-one-strip.tif", 1, 8, SAMPLEFORMAT_UINT, PLANARCONFIG_CONTIG,
                                           COMPRESSION_ADOBE_DEFLATE, 0, 700, true}}) {
        SCOPED_TRACE(l.name);
        const std::string path = dir.file(l.name);
        writeTiff(path, l, 700, 700); // one strip of 1.4 MB decoded, more than a 1 MB cache's quarter
        EXPECT_EQ(TiffBlockReader::open(path, RasterSource::describe(path), 1), nullptr);
        expectSameAsOpenImageIO(path, 1);
    }
}

// float64, tiled or striped, with or without the floating-point predictor, one band or in
// planes, in blocks or in strips beyond the cache: read as float32, each value to the nearest.
// (OpenImageIO 2.4 reads tiled float64 TIFFs as zeros: the values are the reference here.)
TEST(RasterReaders, Float64TiffsReadTheirValues) {
    test::TempDir dir;
    const uint16_t fp = SAMPLEFORMAT_IEEEFP, one = PLANARCONFIG_CONTIG, deflate = COMPRESSION_ADOBE_DEFLATE;
    const std::vector<std::pair<TiffLayout, int>> layouts = {
        {{"f64-tiled.tif", 1, 64, fp, one, deflate, 16}, 256},
        {{"f64-tiled-predictor.tif", 1, 64, fp, one, deflate, 16, 0, false, PREDICTOR_FLOATINGPOINT}, 256},
        {{"f64-lzw-strips.tif", 1, 64, fp, one, COMPRESSION_LZW, 0, 5}, 256},
        {{"f64x2-planes.tif", 2, 64, fp, PLANARCONFIG_SEPARATE, deflate, 0, 6}, 256},
        // One strip of 700 x 700 x 8 bytes, beyond a quarter of 1 MB: streamed, or (with the
        // predictor) through libtiff's scanlines.
        {{"f64-one-strip.tif", 1, 64, fp, one, deflate, 0, 700}, 1},
        {{"f64-one-strip-predictor.tif", 1, 64, fp, one, deflate, 0, 700, false, PREDICTOR_FLOATINGPOINT}, 1},
    };
    for (const auto& [l, cacheMegabytes] : layouts) {
        SCOPED_TRACE(l.name);
        const int w = cacheMegabytes == 1 ? 700 : 61, h = cacheMegabytes == 1 ? 700 : 37;
        const std::string path = dir.file(l.name);
        writeTiff(path, l, w, h);
        const auto source = RasterSource::open(path, cacheMegabytes);
        ASSERT_EQ(source->info().type, SampleType::Float64);
        ASSERT_EQ(source->info().channels, l.channels);
        EXPECT_NE(TiffBlockReader::open(path, source->info(), cacheMegabytes), nullptr);
        for (int c = 0; c < l.channels; ++c) {
            std::vector<float> values(static_cast<size_t>(w * h));
            source->readFloat(0, 0, w, h, c, values.data());
            int wrong = 0;
            for (int y = 0; y < h; ++y) {
                for (int x = 0; x < w; ++x) {
                    wrong += values[static_cast<size_t>(y * w + x)] != static_cast<float>(valueAt(l, x, y, c));
                }
            }
            EXPECT_EQ(wrong, 0) << "channel " << c;
        }
    }
}

} // namespace
} // namespace pyramid
