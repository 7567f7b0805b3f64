// PNG files decoded by libpng alone, without the image I/O module, with the samples OpenImageIO's
// PNG reader gives: every colour type and depth, a palette widened to its colours, grey of 1, 2
// or 4 bits scaled to 8, a transparency chunk made an alpha channel; and the rows read while a
// thread of their own decodes them, a damaged file refused in one line naming it.
#include <gtest/gtest.h>

#include <png.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/png_raster_reader.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/oiio_reference.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using test::expectSameAsOpenImageIO;

// A PNG written with libpng's own calls, for the layouts its simplified writer does not make:
// `colour` and `depth` as the header says (samples given one per byte, or per 16-bit value, and
// packed by libpng), a palette of `entries` colours, and, when `transparent`, a transparency
// chunk: alphas for the palette's entries, or one grey or RGB colour.
struct PngLayout {
    std::string name;
    int colour, depth;
    bool transparent = false, interlaced = false;
    int entries = 0;
};

// The samples of a pixel as the file stores it (one, an index, for a palette).
int channelsOf(int colour) {
    switch (colour) {
    case PNG_COLOR_TYPE_GRAY_ALPHA: return 2;
    case PNG_COLOR_TYPE_RGB: return 3;
    case PNG_COLOR_TYPE_RGB_ALPHA: return 4;
    default: return 1; // grey, palette
    }
}

void writePng(const std::string& path, const PngLayout& l, int w, int h) {
    std::FILE* file = std::fopen(path.c_str(), "wb");
    ASSERT_NE(file, nullptr) << path;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    ASSERT_TRUE(png && info);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        std::fclose(file);
        FAIL() << "libpng could not write " << path;
    }
    png_init_io(png, file);
    png_set_IHDR(png, info, static_cast<png_uint_32>(w), static_cast<png_uint_32>(h), l.depth, l.colour,
                 l.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    const int top = (1 << l.depth) - 1; // the largest sample (an index, for a palette)
    std::vector<png_color> palette;
    std::vector<png_byte> alphas;
    if (l.colour == PNG_COLOR_TYPE_PALETTE) {
        for (int e = 0; e < l.entries; ++e) {
            palette.push_back({static_cast<png_byte>(e * 37 + 5), static_cast<png_byte>(250 - e * 11),
                               static_cast<png_byte>((e * e * 13) % 256)});
            alphas.push_back(static_cast<png_byte>(e * 53 % 256)); // not every entry opaque
        }
        png_set_PLTE(png, info, palette.data(), l.entries);
        if (l.transparent) {
            // Fewer alphas than entries: the rest are opaque.
            png_set_tRNS(png, info, alphas.data(), std::max(1, l.entries - 2), nullptr);
        }
    } else if (l.transparent) {
        png_color_16 key{};
        key.gray = static_cast<png_uint_16>(top / 3);
        key.red = static_cast<png_uint_16>(top / 3);
        key.green = static_cast<png_uint_16>(top / 5);
        key.blue = static_cast<png_uint_16>(top / 7);
        png_set_tRNS(png, info, nullptr, 0, &key);
    }
    png_write_info(png, info);
    if (l.depth == 16) {
        png_set_swap(png); // the rows below hold host-order 16-bit values
    }
    if (l.depth < 8) {
        png_set_packing(png); // one sample per byte below, packed by libpng
    }
    const int passes = png_set_interlace_handling(png);
    const int n = channelsOf(l.colour);
    const int limit = l.colour == PNG_COLOR_TYPE_PALETTE ? l.entries - 1 : top;
    const bool keyed = l.transparent && l.colour != PNG_COLOR_TYPE_PALETTE;
    // Every value, and the transparent colour on every fourth pixel of every fifth row.
    const auto sample = [&](int x, int y, int c) {
        if (keyed && y % 5 == 0 && x % 4 == 0) {
            return c == 0 ? top / 3 : c == 1 ? top / 5 : top / 7;
        }
        return ((x * n + c) * 7 + y * 13 + x * (y % 3)) % (limit + 1);
    };
    std::vector<uint16_t> row(static_cast<size_t>(w * n));
    std::vector<png_byte> bytes(row.size());
    for (int pass = 0; pass < passes; ++pass) {
        for (int y = 0; y < h; ++y) {
            for (int k = 0; k < w * n; ++k) {
                row[static_cast<size_t>(k)] = static_cast<uint16_t>(sample(k / n, y, k % n));
                bytes[static_cast<size_t>(k)] = static_cast<png_byte>(row[static_cast<size_t>(k)]);
            }
            png_write_row(png, l.depth == 16 ? reinterpret_cast<png_bytep>(row.data()) : bytes.data());
        }
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
}

// Every layout the format has, decoded by libpng here (not left to the module), reads as
// OpenImageIO reads it: the palettes of 1 to 8 bits with and without alphas, grey of 1 to 16
// bits with and without a transparent grey, RGB of 8 and 16 bits with a transparent colour,
// interlaced ones too.
TEST(RasterReaders, EveryPngLayoutReadsAsOpenImageIOReadsIt) {
    test::TempDir dir;
    const std::vector<PngLayout> layouts = {
        {"palette1.png", PNG_COLOR_TYPE_PALETTE, 1, false, false, 2},
        {"palette2-alpha.png", PNG_COLOR_TYPE_PALETTE, 2, true, false, 4},
        {"palette4.png", PNG_COLOR_TYPE_PALETTE, 4, false, false, 13},
        {"palette4-alpha.png", PNG_COLOR_TYPE_PALETTE, 4, true, false, 16},
        {"palette8.png", PNG_COLOR_TYPE_PALETTE, 8, false, false, 256},
        {"palette8-alpha-interlaced.png", PNG_COLOR_TYPE_PALETTE, 8, true, true, 200},
        {"grey1.png", PNG_COLOR_TYPE_GRAY, 1},
        {"grey2.png", PNG_COLOR_TYPE_GRAY, 2},
        {"grey4-key.png", PNG_COLOR_TYPE_GRAY, 4, true},
        {"grey8-key.png", PNG_COLOR_TYPE_GRAY, 8, true},
        {"grey16-key-interlaced.png", PNG_COLOR_TYPE_GRAY, 16, true, true},
        {"rgb8-key.png", PNG_COLOR_TYPE_RGB, 8, true},
        {"rgb16-key.png", PNG_COLOR_TYPE_RGB, 16, true},
        {"greyalpha8.png", PNG_COLOR_TYPE_GRAY_ALPHA, 8},
        {"rgba16.png", PNG_COLOR_TYPE_RGB_ALPHA, 16},
    };
    for (const PngLayout& l : layouts) {
        SCOPED_TRACE(l.name);
        const std::string path = dir.file(l.name);
        writePng(path, l, 61, 37);
        EXPECT_NE(openPngRaster(path, 256), nullptr);
        const RasterInfo info = RasterSource::describe(path);
        const int channels = l.colour == PNG_COLOR_TYPE_PALETTE ? 3 : channelsOf(l.colour);
        EXPECT_EQ(info.channels, channels + (l.transparent ? 1 : 0));
        EXPECT_EQ(info.type, l.depth == 16 ? SampleType::UInt16 : SampleType::UInt8);
        expectSameAsOpenImageIO(path);
    }
}

// A palette PNG as libpng's simplified writer makes one, with and without alphas.
TEST(RasterReaders, PalettePngIsExpandedAsOpenImageIODoes) {
    test::TempDir dir;
    const int w = 61, h = 37;
    const uint8_t colours[4 * 4] = {10, 20, 30, 255, 200, 100, 0, 255, 0, 255, 128, 90, 77, 77, 77, 0};
    std::vector<uint8_t> indices(static_cast<size_t>(w * h));
    for (size_t k = 0; k < indices.size(); ++k) {
        indices[k] = static_cast<uint8_t>((k * 7) % 4);
    }
    for (const bool transparent : {false, true}) {
        png_image image{};
        image.version = PNG_IMAGE_VERSION;
        image.width = w;
        image.height = h;
        image.format = transparent ? PNG_FORMAT_RGBA_COLORMAP : PNG_FORMAT_RGB_COLORMAP;
        image.colormap_entries = 4;
        std::vector<uint8_t> map;
        for (int c = 0; c < 4; ++c) {
            map.insert(map.end(), colours + 4 * c, colours + 4 * c + (transparent ? 4 : 3));
        }
        const std::string path = dir.file(transparent ? "palette-alpha.png" : "palette.png");
        ASSERT_TRUE(png_image_write_to_file(&image, path.c_str(), 0, indices.data(), 0, map.data())) << image.message;
        EXPECT_NE(openPngRaster(path, 256), nullptr);
        expectSameAsOpenImageIO(path);
    }
}

// A PNG is decoded by a thread of its own while it is read: windows read from several threads
// at once, in any order (last rows first too), are the file's samples; a file cut short gives
// its first rows and then the error, to every read that needs the rows it lacks, and so does a
// file with a damaged byte; a reader closed at once stops its decoding.
TEST(RasterReaders, PngRowsAreReadWhileTheyAreDecoded) {
    test::TempDir dir;
    const int w = 97, h = 1500;
    std::vector<uint8_t> pixels(static_cast<size_t>(w) * h * 3);
    for (size_t k = 0; k < pixels.size(); ++k) {
        pixels[k] = static_cast<uint8_t>((k * 2654435761u) >> 24);
    }
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = w;
    image.height = h;
    image.format = PNG_FORMAT_RGB;
    const std::string path = dir.file("tall.png");
    ASSERT_TRUE(png_image_write_to_file(&image, path.c_str(), 0, pixels.data(), 0, nullptr)) << image.message;

    const auto source = RasterSource::open(path);
    std::vector<std::string> failures(4);
    std::vector<std::thread> readers;
    for (int t = 0; t < 4; ++t) {
        readers.emplace_back([&, t] {
            // Thread t reads bands of 37 rows, from the south for odd t.
            for (int b = 0; b * 37 < h; ++b) {
                const int y0 = (t % 2 ? (h - 1) / 37 - b : b) * 37, y1 = std::min(h, y0 + 37);
                std::vector<uint16_t> window(static_cast<size_t>(w) * (y1 - y0) * 3);
                source->readUInt16(0, y0, w, y1, 0, 3, window.data());
                for (size_t k = 0; k < window.size(); ++k) {
                    if (window[k] != pixels[static_cast<size_t>(y0) * w * 3 + k]) {
                        failures[static_cast<size_t>(t)] = "row " + std::to_string(y0 + k / (w * 3));
                        return;
                    }
                }
            }
        });
    }
    for (std::thread& r : readers) {
        r.join();
    }
    for (const std::string& f : failures) {
        EXPECT_EQ(f, "");
    }

    // Cut short: the first rows read, the last ones fail with the file's name and the problem.
    const std::string whole = test::readFile(path);
    const std::string cut = dir.file("cut.png");
    {
        std::FILE* f = std::fopen(cut.c_str(), "wb");
        std::fwrite(whole.data(), 1, whole.size() / 2, f);
        std::fclose(f);
    }
    const auto partial = RasterSource::open(cut);
    std::vector<uint16_t> row(static_cast<size_t>(w) * 3);
    partial->readUInt16(0, 10, w, 11, 0, 3, row.data());
    EXPECT_EQ(row[0], pixels[static_cast<size_t>(10) * w * 3]);
    for (int attempt = 0; attempt < 2; ++attempt) {
        try {
            partial->readUInt16(0, h - 1, w, h, 0, 3, row.data());
            ADD_FAILURE() << "the last row of a file cut in half was read";
        } catch (const std::exception& e) {
            EXPECT_EQ(std::string(e.what()), cut + ": cannot read: damaged or truncated PNG (Read Error)");
        }
    }
    // One byte changed in the first image data chunk's CRC: the pixels decode, but the chunk is
    // damaged (the decoder leaves the zlib stream's own checksum unchecked, not the CRCs).
    std::string flipped = whole;
    const size_t data = flipped.find("IDAT");
    ASSERT_NE(data, std::string::npos);
    ASSERT_GE(data, size_t{4});
    size_t length = 0; // the chunk's length, big-endian, before its type
    for (size_t k = data - 4; k < data; ++k) {
        length = length << 8 | static_cast<uint8_t>(whole[k]);
    }
    ASSERT_LT(data + 4 + length + 4, whole.size());
    flipped[data + 4 + length] ^= 0x10;
    const std::string damagedPath = dir.file("damaged.png");
    {
        std::FILE* f = std::fopen(damagedPath.c_str(), "wb");
        std::fwrite(flipped.data(), 1, flipped.size(), f);
        std::fclose(f);
    }
    const auto damagedSource = RasterSource::open(damagedPath);
    try {
        damagedSource->readUInt16(0, h - 1, w, h, 0, 3, row.data());
        ADD_FAILURE() << "the last row of a damaged file was read";
    } catch (const std::exception& e) {
        EXPECT_EQ(std::string(e.what()), damagedPath + ": cannot read: damaged or truncated PNG (IDAT: CRC error)");
    }
    // A text chunk with a bad CRC before the image data: an ancillary chunk, which libpng would
    // only warn about and drop; a damaged file is refused whole.
    std::string text = whole;
    const std::string chunk = std::string("\0\0\0\x07tEXtTitle\0x", 15) + std::string(4, '\0'); // CRC 0: wrong
    text.insert(8 + 25, chunk); // after the signature and IHDR
    const std::string textPath = dir.file("bad-text.png");
    {
        std::FILE* f = std::fopen(textPath.c_str(), "wb");
        std::fwrite(text.data(), 1, text.size(), f);
        std::fclose(f);
    }
    try {
        RasterSource::open(textPath)->readUInt16(0, h - 1, w, h, 0, 3, row.data());
        ADD_FAILURE() << "a file with a damaged text chunk was read";
    } catch (const std::exception& e) {
        EXPECT_EQ(std::string(e.what()), textPath + ": cannot read: damaged or truncated PNG (tEXt: CRC error)");
    }
    // Opened and closed at once: the decoding thread stops (a leak or a late write would show
    // under the sanitizers).
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(RasterSource::open(path)->info().height, h);
    }
}

} // namespace
} // namespace pyramid
