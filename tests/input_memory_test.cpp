// Inputs in bounded memory: every TIFF layout real DEMs and imagery ship in (strips, tiles, one
// strip for the whole image, BigTIFF, both byte orders, each predictor, one band or interleaved
// RGB, RGBA, grey and alpha) reads the file's samples through
// the block cache and, for strips larger than the cache, through the strip stream and its
// scratch file; a PNG larger than the cache reads back from its scratch file; blocks no image
// has and tiles beyond the cache are refused with one line; the block cache decodes a block
// once however many threads want it, and recycles its buffers within the budget.
#include <gtest/gtest.h>

#include <png.h>
#include <tiffio.h>

#include <atomic>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/block_cache.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

struct TiffLayout {
    std::string name;
    uint16_t bits = 32;
    uint16_t format = SAMPLEFORMAT_IEEEFP;
    uint16_t compression = COMPRESSION_ADOBE_DEFLATE;
    uint16_t predictor = PREDICTOR_NONE;
    uint32_t tile = 0;          // 0: strips
    uint32_t rowsPerStrip = 16; // strips only
    const char* mode = "w";     // "w8": BigTIFF; "wb": big-endian
    uint16_t channels = 1;      // interleaved; RGB from 3
    uint16_t planar = PLANARCONFIG_CONTIG; // or PLANARCONFIG_SEPARATE (strips only)
};

// Sample (x, y) of the test images, exact in every sample type (within the type's range).
double sampleAt(const TiffLayout& l, uint32_t x, uint32_t y) {
    const double v = static_cast<double>((x * 37 + y * 101) % 997) - (l.format == SAMPLEFORMAT_UINT ? 0.0 : 400.0);
    if (l.format == SAMPLEFORMAT_IEEEFP) {
        return v + 0.25 * static_cast<double>((x + y) % 4);
    }
    return l.bits == 8 ? static_cast<double>(static_cast<int>(v) % 100) : v;
}

// Channel c of sample (x, y): channel 0 is sampleAt, the others 30 x c above it.
double sampleOf(const TiffLayout& l, uint32_t x, uint32_t y, uint32_t c) {
    return sampleAt(l, x, y) + 30.0 * c;
}

void putSample(const TiffLayout& l, double v, uint8_t* to) {
    if (l.format == SAMPLEFORMAT_IEEEFP) {
        const auto f = static_cast<float>(v);
        std::memcpy(to, &f, 4);
    } else if (l.bits == 8) {
        const auto b = static_cast<int8_t>(v);
        std::memcpy(to, &b, 1);
    } else if (l.bits == 16) {
        const auto s = static_cast<int16_t>(v);
        std::memcpy(to, &s, 2);
    } else {
        const auto i = static_cast<int32_t>(v);
        std::memcpy(to, &i, 4);
    }
}

void writeTiff(const std::string& path, const TiffLayout& l, uint32_t w, uint32_t h) {
    TIFF* t = TIFFOpen(path.c_str(), l.mode);
    ASSERT_TRUE(t) << path;
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, w);
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, h);
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, l.bits);
    TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, l.format);
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, l.channels);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, l.channels >= 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
    if (l.channels == 2 || l.channels == 4) {
        const uint16_t alpha = EXTRASAMPLE_UNASSALPHA;
        TIFFSetField(t, TIFFTAG_EXTRASAMPLES, uint16_t{1}, &alpha);
    }
    TIFFSetField(t, TIFFTAG_PLANARCONFIG, l.planar);
    TIFFSetField(t, TIFFTAG_COMPRESSION, l.compression);
    if (l.predictor != PREDICTOR_NONE) {
        TIFFSetField(t, TIFFTAG_PREDICTOR, l.predictor);
    }
    const size_t bytes = l.bits / 8u * l.channels; // of a pixel
    const size_t sampleBytes = l.bits / 8u;
    const auto putPixel = [&](uint32_t x, uint32_t y, uint8_t* to) {
        for (uint32_t c = 0; c < l.channels; ++c) {
            putSample(l, sampleOf(l, x, y, c), to + c * sampleBytes);
        }
    };
    if (l.tile) {
        TIFFSetField(t, TIFFTAG_TILEWIDTH, l.tile);
        TIFFSetField(t, TIFFTAG_TILELENGTH, l.tile);
        std::vector<uint8_t> tile(static_cast<size_t>(l.tile) * l.tile * bytes);
        for (uint32_t ty = 0; ty < h; ty += l.tile) {
            for (uint32_t tx = 0; tx < w; tx += l.tile) {
                std::fill(tile.begin(), tile.end(), uint8_t{0});
                for (uint32_t y = ty; y < std::min(h, ty + l.tile); ++y) {
                    for (uint32_t x = tx; x < std::min(w, tx + l.tile); ++x) {
                        putPixel(x, y, tile.data() + ((y - ty) * l.tile + (x - tx)) * bytes);
                    }
                }
                ASSERT_GE(TIFFWriteEncodedTile(t, TIFFComputeTile(t, tx, ty, 0, 0), tile.data(),
                                               static_cast<tmsize_t>(tile.size())), 0);
            }
        }
    } else {
        const uint32_t rows = std::min(l.rowsPerStrip, h);
        TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, rows);
        // Separate planes: each channel's strips in turn, a sample per pixel.
        const bool separate = l.planar == PLANARCONFIG_SEPARATE;
        const size_t stored = separate ? sampleBytes : bytes; // of a pixel in a strip
        for (uint16_t plane = 0; plane < (separate ? l.channels : 1); ++plane) {
            for (uint32_t y0 = 0; y0 < h; y0 += rows) {
                const uint32_t n = std::min(rows, h - y0);
                std::vector<uint8_t> strip(static_cast<size_t>(w) * n * stored);
                for (uint32_t y = y0; y < y0 + n; ++y) {
                    for (uint32_t x = 0; x < w; ++x) {
                        uint8_t* to = strip.data() + ((y - y0) * w + x) * stored;
                        if (separate) {
                            putSample(l, sampleOf(l, x, y, plane), to);
                        } else {
                            putPixel(x, y, to);
                        }
                    }
                }
                ASSERT_GE(TIFFWriteEncodedStrip(t, TIFFComputeStrip(t, y0, plane), strip.data(),
                                                static_cast<tmsize_t>(strip.size())), 0);
            }
        }
    }
    TIFFClose(t);
}

// Reads the whole image and a window across block boundaries, from several threads at once.
void expectSamples(const std::string& path, const TiffLayout& l, uint32_t w, uint32_t h, int cacheMegabytes) {
    SCOPED_TRACE(path + " with a cache of " + std::to_string(cacheMegabytes) + " MB");
    const auto source = RasterSource::open(path, cacheMegabytes);
    ASSERT_EQ(source->info().width, static_cast<int>(w));
    std::vector<std::string> failures(3);
    std::vector<std::thread> threads;
    for (int t = 0; t < 3; ++t) {
        threads.emplace_back([&, t] {
            const int x0 = t == 0 ? 0 : 7 * t, y0 = t == 0 ? 0 : 5 + 9 * t;
            const int x1 = static_cast<int>(w) - (t == 0 ? 0 : 3), y1 = static_cast<int>(h) - (t == 0 ? 0 : 11);
            const size_t area = static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0);
            std::vector<float> out(area);
            // Each channel alone as float32, and for 8/16-bit unsigned samples the channels
            // [1, channels) together as uint16 (and as bytes for 8 bits), interleaved.
            const uint32_t first = l.channels > 1 ? 1 : 0, wanted = l.channels - first;
            const bool unsignedSmall = l.format == SAMPLEFORMAT_UINT && l.bits <= 16;
            std::vector<uint16_t> words(unsignedSmall ? area * wanted : 0);
            std::vector<uint8_t> bytes(unsignedSmall && l.bits == 8 ? area * wanted : 0);
            if (unsignedSmall) {
                source->readUInt16(x0, y0, x1, y1, static_cast<int>(first), l.channels, words.data());
            }
            if (!bytes.empty()) {
                source->readUInt8(x0, y0, x1, y1, static_cast<int>(first), l.channels, bytes.data(),
                                  static_cast<std::ptrdiff_t>(x1 - x0) * wanted);
            }
            for (uint32_t c = 0; c < l.channels; ++c) {
                source->readFloat(x0, y0, x1, y1, static_cast<int>(c), out.data());
                for (int y = y0; y < y1; ++y) {
                    for (int x = x0; x < x1; ++x) {
                        const size_t k = static_cast<size_t>(y - y0) * static_cast<size_t>(x1 - x0) + static_cast<size_t>(x - x0);
                        const auto want = static_cast<float>(sampleOf(l, static_cast<uint32_t>(x), static_cast<uint32_t>(y), c));
                        float got = out[k];
                        std::string how = "float";
                        if (got == want && c >= first && unsignedSmall) {
                            got = words[k * wanted + (c - first)];
                            how = "uint16";
                            if (got == want && !bytes.empty()) {
                                got = bytes[k * wanted + (c - first)];
                                how = "uint8";
                            }
                        }
                        if (got != want) {
                            failures[static_cast<size_t>(t)] = "(" + std::to_string(x) + "," + std::to_string(y) +
                                                               ") channel " + std::to_string(c) + " as " + how + ": " +
                                                               std::to_string(got) + " instead of " + std::to_string(want);
                            return;
                        }
                    }
                }
            }
        });
    }
    for (std::thread& t : threads) {
        t.join();
    }
    for (const std::string& f : failures) {
        EXPECT_EQ(f, "");
    }
}

TEST(InputMemory, EveryTiffLayoutReadsItsSamples) {
    const std::vector<TiffLayout> layouts = {
        {"f32-deflate-p3-tiled.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_FLOATINGPOINT, 128},
        {"f32-lzw-p3-strips.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_LZW, PREDICTOR_FLOATINGPOINT, 0, 16},
        {"f32-deflate-rows.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 0, 1},
        {"f32-deflate-p3-one-strip.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_FLOATINGPOINT, 0, 100000},
        {"f32-deflate-one-strip-be.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 0, 100000, "wb"},
        {"i16-deflate-p2-one-strip-be.tif", 16, SAMPLEFORMAT_INT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 0, 100000, "wb"},
        {"i16-deflate-p2-one-strip.tif", 16, SAMPLEFORMAT_INT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 0, 100000},
        {"u16-none-one-strip.tif", 16, SAMPLEFORMAT_UINT, COMPRESSION_NONE, PREDICTOR_NONE, 0, 100000},
        {"i32-lzw-one-strip.tif", 32, SAMPLEFORMAT_INT, COMPRESSION_LZW, PREDICTOR_HORIZONTAL, 0, 100000},
        {"i8-packbits-strips.tif", 8, SAMPLEFORMAT_INT, COMPRESSION_PACKBITS, PREDICTOR_NONE, 0, 7},
        {"f32-zstd-tiled.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ZSTD, PREDICTOR_FLOATINGPOINT, 64},
        {"f32-lzma-strips.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_LZMA, PREDICTOR_NONE, 0, 32},
        {"f32-bigtiff-tiled.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_FLOATINGPOINT, 128, 0, "w8"},
        {"i16-bigtiff-one-strip.tif", 16, SAMPLEFORMAT_INT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 0, 100000, "w8"},
        // Imagery: interleaved bands (RGB, RGBA, grey and alpha).
        {"rgb8-deflate-tiled.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 128, 0, "w", 3},
        {"rgb8-deflate-one-strip.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 0, 100000, "w", 3},
        {"rgb8-lzw-p2-one-strip.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_LZW, PREDICTOR_HORIZONTAL, 0, 100000, "w", 3},
        {"rgba16-deflate-p2-one-strip-be.tif", 16, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 0, 100000, "wb", 4},
        {"rgba16-none-one-strip-be.tif", 16, SAMPLEFORMAT_UINT, COMPRESSION_NONE, PREDICTOR_NONE, 0, 100000, "wb", 4},
        {"ga8-packbits-strips.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_PACKBITS, PREDICTOR_NONE, 0, 7, "w", 2},
        {"rgb8-zstd-bigtiff-tiled.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_ZSTD, PREDICTOR_NONE, 64, 0, "w8", 3},
    };
    test::TempDir dir;
    // 700 x 530 samples: a one-strip float32 image is 1.4 MB, beyond a quarter of a 1 MB cache,
    // so that its rows go through the strip stream and the scratch file; with 256 MB they are
    // one block of the cache.
    const uint32_t w = 700, h = 530;
    for (const TiffLayout& l : layouts) {
        if (!TIFFIsCODECConfigured(l.compression)) {
            continue; // a libtiff built without ZSTD or LZMA
        }
        const std::string path = dir.file(l.name);
        writeTiff(path, l, w, h);
        expectSamples(path, l, w, h, 256);
        if (!l.tile) {
            expectSamples(path, l, w, h, 1);
        }
    }
}

std::string errorOf(const std::string& path, int cacheMegabytes) {
    try {
        const auto source = RasterSource::open(path, cacheMegabytes);
        std::vector<float> one(1);
        source->readFloat(0, 0, 1, 1, 0, one.data());
    } catch (const OptionError& e) {
        return "option " + e.option() + ": " + e.problem();
    } catch (const Error& e) {
        return e.what();
    }
    return "no error";
}

TEST(InputMemory, BlocksNoImageHasAndTilesBeyondTheCacheAreRefused) {
    test::TempDir dir;
    // A 40 x 30 image declaring 65536 x 65536 tiles: refused before 16 GiB are asked for.
    const std::string hostile = dir.file("hostile.tif");
    {
        TIFF* t = TIFFOpen(hostile.c_str(), "w");
        ASSERT_TRUE(t);
        TIFFSetField(t, TIFFTAG_IMAGEWIDTH, 40);
        TIFFSetField(t, TIFFTAG_IMAGELENGTH, 30);
        TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 32);
        TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP);
        TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
        TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
        TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
        TIFFSetField(t, TIFFTAG_TILEWIDTH, 65536);
        TIFFSetField(t, TIFFTAG_TILELENGTH, 65536);
        std::vector<uint8_t> nothing(16);
        TIFFWriteRawTile(t, 0, nothing.data(), static_cast<tmsize_t>(nothing.size()));
        TIFFClose(t);
    }
    const std::string hostileError = errorOf(hostile, 256);
    EXPECT_NE(hostileError.find("hostile.tif: damaged TIFF: tiles of 65536 x 65536 samples for a 40 x 30 image"),
              std::string::npos)
        << hostileError;
    // 512 x 512 float32 tiles are 1 MB decoded: a 1 MB cache cannot hold the four a window needs.
    const TiffLayout big{"big-tiles.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 512};
    writeTiff(dir.file(big.name), big, 600, 520);
    const std::string bigError = errorOf(dir.file(big.name), 1);
    EXPECT_NE(bigError.find("option cacheMegabytes: "), std::string::npos) << bigError;
    EXPECT_NE(bigError.find("tiles of 512 x 512 samples (1 MB decoded) need a cache of at least 4 MB, not 1"),
              std::string::npos)
        << bigError;
    expectSamples(dir.file(big.name), big, 600, 520, 4);
    // The cache counts blocks as decoded, in the file's own sample type: 512 x 512 RGB tiles of
    // 8 bits are 768 KB, which a 4 MB cache holds four of (as float32 they would need 12 MB);
    // of 16 bits, 1.5 MB, which need 8 MB.
    const TiffLayout rgb{"rgb8-big-tiles.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL,
                         512, 0, "w", 3};
    writeTiff(dir.file(rgb.name), rgb, 600, 520);
    expectSamples(dir.file(rgb.name), rgb, 600, 520, 4);
    const TiffLayout rgb16{"rgb16-big-tiles.tif", 16, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE,
                           512, 0, "w", 3};
    writeTiff(dir.file(rgb16.name), rgb16, 600, 520);
    const std::string rgb16Error = errorOf(dir.file(rgb16.name), 4);
    EXPECT_NE(rgb16Error.find("tiles of 512 x 512 samples (2 MB decoded) need a cache of at least 8 MB, not 4"),
              std::string::npos)
        << rgb16Error;
    expectSamples(dir.file(rgb16.name), rgb16, 600, 520, 8);
    // Tiles larger than a small image, as COG writers make them, are fine.
    const TiffLayout small{"small.tif", 16, SAMPLEFORMAT_INT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 512};
    writeTiff(dir.file(small.name), small, 300, 200);
    expectSamples(dir.file(small.name), small, 300, 200, 256);
}

// Points entry `index` of the offsets of `tag` (StripOffsets 273, TileOffsets 324) in the first
// directory of a little-endian BigTIFF at `offset`.
void setBigTiffOffset(const std::string& path, uint16_t tag, uint32_t index, uint64_t offset) {
    std::string bytes = test::readFile(path);
    const auto u16 = [&](uint64_t at) {
        uint16_t v = 0;
        std::memcpy(&v, &bytes.at(static_cast<size_t>(at)), 2);
        return v;
    };
    const auto u64 = [&](uint64_t at) {
        uint64_t v = 0;
        std::memcpy(&v, &bytes.at(static_cast<size_t>(at)), 8);
        return v;
    };
    ASSERT_EQ(bytes.substr(0, 4), std::string("II+\0", 4)) << path;
    const uint64_t ifd = u64(8);
    for (uint64_t e = 0; e < u64(ifd); ++e) {
        const uint64_t at = ifd + 8 + e * 20; // tag, type, count (8 bytes), value or its offset (8 bytes)
        if (u16(at) != tag) {
            continue;
        }
        ASSERT_EQ(u16(at + 2), TIFF_LONG8) << path;
        const uint64_t values = u64(at + 4) == 1 ? at + 12 : u64(at + 12);
        std::memcpy(&bytes.at(static_cast<size_t>(values + uint64_t{index} * 8)), &offset, 8);
        std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
        return;
    }
    FAIL() << path << ": no tag " << tag;
}

// A block whose offset lies far beyond the end of the file (2^63 - 15, which read() refuses
// outright): an error naming the file and the block, for tiles in the cache and for a strip
// beyond the cache, streamed through libtiff (LZW).
TEST(InputMemory, ABlockBeyondTheEndOfTheFileIsAnError) {
    if constexpr (std::endian::native != std::endian::little) {
        GTEST_SKIP() << "the test patches a little-endian file in place";
    }
    test::TempDir dir;
    // Writes `l` (w x h), points entry `index` of `tag` far away, and reads a pixel.
    const auto expectRefused = [&](const TiffLayout& l, uint32_t w, uint32_t h, uint16_t tag, uint32_t index,
                                   int cacheMegabytes, const std::string& message) {
        const std::string path = dir.file(l.name);
        writeTiff(path, l, w, h);
        setBigTiffOffset(path, tag, index, (uint64_t{1} << 63) - 15);
        const std::string error = errorOf(path, cacheMegabytes);
        EXPECT_NE(error.find(path + ": " + message), std::string::npos) << error;
    };
    const TiffLayout tiles{"far-tile.tif", 16, SAMPLEFORMAT_INT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 16,
                           0, "w8"};
    expectRefused(tiles, 40, 24, TIFFTAG_TILEOFFSETS, 0, 1, "damaged TIFF: tile 0 lies beyond the end of the file");
    // 700 x 530 int16 samples in one strip: beyond a quarter of a 1 MB cache.
    const TiffLayout strip{"far-strip.tif", 16, SAMPLEFORMAT_INT, COMPRESSION_LZW, PREDICTOR_NONE, 0, 100000, "w8"};
    expectRefused(strip, 700, 530, TIFFTAG_STRIPOFFSETS, 0, 1,
                  "damaged TIFF: strip 0 lies beyond the end of the file");
    // RGB in separate planes: the third plane's strip, which the block's decoding reads last.
    const TiffLayout planes{"far-planes.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_NONE, PREDICTOR_NONE, 0, 24, "w8", 3,
                            PLANARCONFIG_SEPARATE};
    expectRefused(planes, 40, 24, TIFFTAG_STRIPOFFSETS, 2, 256, "damaged TIFF: strip 2 lies beyond the end of the file");
    // Planes in strips beyond a quarter of a 1 MB cache, left to OpenImageIO (which reads through
    // libtiff too): refused before it reads.
    const TiffLayout bigPlanes{"far-plane-strips.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_NONE, PREDICTOR_NONE, 0, 100000,
                               "w8", 3, PLANARCONFIG_SEPARATE};
    expectRefused(bigPlanes, 700, 530, TIFFTAG_STRIPOFFSETS, 2, 1,
                  "cannot read: damaged TIFF: strip 2 lies beyond the end of the file");
}

// A PNG larger than the cache is decoded into its scratch file and reads the same samples; an
// interlaced one, which decodes whole, must fit the cache to be read, not to be described.
TEST(InputMemory, PngBeyondTheCacheReadsFromItsScratchFile) {
    test::TempDir dir;
    const int w = 800, h = 700; // 16-bit RGB: 3.4 MB
    std::vector<uint16_t> pixels(static_cast<size_t>(w) * h * 3);
    for (size_t k = 0; k < pixels.size(); ++k) {
        pixels[k] = static_cast<uint16_t>((k * 2654435761u) >> 16);
    }
    for (const bool interlaced : {false, true}) {
        const std::string path = dir.file(interlaced ? "interlaced.png" : "plain.png");
        std::FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_TRUE(f);
        png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
        png_infop info = png_create_info_struct(png);
        png_init_io(png, f);
        png_set_IHDR(png, info, w, h, 16, PNG_COLOR_TYPE_RGB, interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        png_write_info(png, info);
        png_set_swap(png);
        std::vector<png_bytep> rows(static_cast<size_t>(h));
        for (int y = 0; y < h; ++y) {
            rows[static_cast<size_t>(y)] = reinterpret_cast<png_bytep>(pixels.data() + static_cast<size_t>(y) * w * 3);
        }
        png_write_image(png, rows.data());
        png_write_end(png, nullptr);
        png_destroy_write_struct(&png, &info);
        std::fclose(f);
        // Described from the header whatever the cache (a mosaic describes its inputs first).
        const RasterInfo described = RasterSource::describe(path);
        EXPECT_EQ(described.width, w);
        EXPECT_EQ(described.channels, 3);
        if (interlaced) {
            const std::string error = errorOf(path, 1);
            EXPECT_NE(error.find("option cacheMegabytes: " + path + ": an interlaced PNG is decoded whole, 4 MB"),
                      std::string::npos)
                << error;
            continue;
        }
        const auto source = RasterSource::open(path, 1);
        std::vector<uint16_t> window(static_cast<size_t>(w - 10) * 300 * 2);
        source->readUInt16(5, 350, w - 5, 650, 1, 3, window.data());
        for (int y = 350; y < 650; ++y) {
            for (int x = 5; x < w - 5; ++x) {
                for (int c = 1; c < 3; ++c) {
                    ASSERT_EQ(window[(static_cast<size_t>(y - 350) * (w - 10) + (x - 5)) * 2 + (c - 1)],
                              pixels[(static_cast<size_t>(y) * w + x) * 3 + c])
                        << x << "," << y << "," << c;
                }
            }
        }
    }
}

// The input fuzzer's seeds are valid files of the layouts they name: each reads whole, with the
// fuzzer's 1 MB cache.
TEST(InputMemory, FuzzSeedsAreValidInputs) {
    int files = 0;
    for (const auto& f : std::filesystem::directory_iterator(test::corpusPath("input"))) {
        SCOPED_TRACE(f.path().string());
        const auto source = RasterSource::open(f.path().string(), 1);
        const RasterInfo& info = source->info();
        std::vector<float> all(static_cast<size_t>(info.width) * static_cast<size_t>(info.height));
        for (int c = 0; c < info.channels; ++c) {
            source->readFloat(0, 0, info.width, info.height, c, all.data());
        }
        ++files;
    }
    EXPECT_GE(files, 10);
}

TEST(InputMemory, BlockCacheDecodesOnceAndRecyclesWithinTheBudget) {
    // Room for 4 blocks of 1000 bytes.
    BlockCache cache(4 * 1000, 1000);
    std::atomic<int> decodes{0};
    const auto decodeAs = [&](uint32_t index) {
        return [&, index](BlockCache::Block& b) {
            ++decodes;
            std::this_thread::sleep_for(std::chrono::milliseconds(20)); // others arrive meanwhile
            std::fill(b.begin(), b.end(), static_cast<uint8_t>(index));
        };
    };
    std::vector<std::thread> threads;
    for (int t = 0; t < 6; ++t) {
        threads.emplace_back([&] { EXPECT_EQ((*cache.get(7, decodeAs(7)))[999], 7); });
    }
    for (std::thread& t : threads) {
        t.join();
    }
    EXPECT_EQ(decodes.load(), 1); // six threads, one decode
    for (uint32_t i = 0; i < 50; ++i) {
        EXPECT_EQ((*cache.get(i, decodeAs(i)))[0], i);
    }
    EXPECT_EQ(cache.buffers(), 4u); // recycled, never more than the budget holds
    // Held blocks are not recycled: a fifth buffer when all four are held.
    std::vector<std::shared_ptr<const BlockCache::Block>> held;
    for (uint32_t i = 100; i < 105; ++i) {
        held.push_back(cache.get(i, decodeAs(i)));
    }
    EXPECT_EQ(cache.buffers(), 5u);
    for (uint32_t i = 100; i < 105; ++i) {
        EXPECT_EQ((*held[i - 100])[500], i);
    }
    // A failed decode leaves nothing behind: the next request decodes again.
    EXPECT_THROW(cache.get(200, [](BlockCache::Block&) { throw std::runtime_error("damaged"); }), std::runtime_error);
    EXPECT_EQ((*cache.get(200, decodeAs(200)))[1], 200);
}

} // namespace
} // namespace pyramid
