// The direct readers (libtiff and libpng, no OpenImageIO) describe and read every layout they
// take exactly as OpenImageIO does, and the layouts they leave go through the image I/O
// module with the same results. The reference is OpenImageIO's ImageInput, read in each
// file's own sample type.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <tiffio.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/input/tiff_block_reader.hpp"
#include "tests/support/oiio_reference.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using test::expectSameAsOpenImageIO;

struct Layout {
    std::string name;       // file name; the extension picks the format
    OIIO::TypeDesc type;    // sample type
    int channels;
    std::string compression; // TIFF only; "" = the writer's default
    int tile = 0;           // TIFF only: tile size, 0 = strips
};

// Values that fill the type's range and differ from pixel to pixel and channel to channel.
std::vector<double> valuesFor(const Layout& l, int w, int h) {
    std::vector<double> v(static_cast<size_t>(w * h * l.channels));
    double low = 0, high = 255;
    switch (l.type.basetype) {
    case OIIO::TypeDesc::INT8: low = -128, high = 127; break;
    case OIIO::TypeDesc::UINT16: high = 65535; break;
    case OIIO::TypeDesc::INT16: low = -32768, high = 32767; break;
    case OIIO::TypeDesc::INT32: low = -2e6, high = 2e6; break;
    case OIIO::TypeDesc::FLOAT: case OIIO::TypeDesc::DOUBLE: low = -431.75, high = 8848.25; break;
    default: break;
    }
    for (size_t k = 0; k < v.size(); ++k) {
        const double t = static_cast<double>((k * 7919) % v.size()) / static_cast<double>(v.size() - 1);
        v[k] = l.type.basetype == OIIO::TypeDesc::FLOAT || l.type.basetype == OIIO::TypeDesc::DOUBLE
                   ? low + (high - low) * t
                   : std::floor(low + (high - low) * t);
    }
    return v;
}

void write(const std::string& path, const Layout& l, int w, int h) {
    const std::vector<double> values = valuesFor(l, w, h);
    OIIO::ImageSpec spec(w, h, l.channels, l.type);
    if (!l.compression.empty()) {
        spec.attribute("compression", l.compression);
    }
    if (l.tile) {
        spec.tile_width = spec.tile_height = l.tile;
    }
    if (l.channels == 2 || l.channels == 4) {
        spec.alpha_channel = l.channels - 1;
        spec.attribute("oiio:UnassociatedAlpha", 1); // store the values as given
    }
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out) << path;
    ASSERT_TRUE(out->open(path, spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::DOUBLE, values.data())) << out->geterror();
    ASSERT_TRUE(out->close());
}

TEST(RasterReaders, EveryLayoutReadsAsOpenImageIOReadsIt) {
    const std::vector<Layout> layouts = {
        // PNG: decoded by libpng.
        {"grey8.png", OIIO::TypeDesc::UINT8, 1, ""},
        {"greyalpha8.png", OIIO::TypeDesc::UINT8, 2, ""},
        {"rgb8.png", OIIO::TypeDesc::UINT8, 3, ""},
        {"rgba8.png", OIIO::TypeDesc::UINT8, 4, ""},
        {"grey16.png", OIIO::TypeDesc::UINT16, 1, ""},
        {"rgba16.png", OIIO::TypeDesc::UINT16, 4, ""},
        // TIFF, read by pread: uncompressed strips.
        {"rgb8-none.tif", OIIO::TypeDesc::UINT8, 3, "none"},
        {"rgba16-none.tif", OIIO::TypeDesc::UINT16, 4, "none"},
        {"f32x2-none.tif", OIIO::TypeDesc::FLOAT, 2, "none"},
        // TIFF, one band, decoded by libtiff block by block.
        {"i16-zip.tif", OIIO::TypeDesc::INT16, 1, "zip"},
        {"u16-lzw-tiled.tif", OIIO::TypeDesc::UINT16, 1, "lzw", 16},
        {"u8-zip.tif", OIIO::TypeDesc::UINT8, 1, "zip"},
        {"i32-none.tif", OIIO::TypeDesc::INT32, 1, "none"},
        {"f32-zip-tiled.tif", OIIO::TypeDesc::FLOAT, 1, "zip", 32},
        {"f32-zip.tif", OIIO::TypeDesc::FLOAT, 1, "zip"}, // strips, the last one short
        // Described by libtiff, read through the module.
        {"rgb8-zip.tif", OIIO::TypeDesc::UINT8, 3, "zip"},
        {"f64-zip.tif", OIIO::TypeDesc::DOUBLE, 1, "zip"},
        {"i8-none.tif", OIIO::TypeDesc::INT8, 1, "none"},
        // Other formats: the module alone.
        {"rgb-half.exr", OIIO::TypeDesc::HALF, 3, ""},
        {"grey-float.exr", OIIO::TypeDesc::FLOAT, 1, ""},
    };
    test::TempDir dir;
    for (const Layout& l : layouts) {
        const std::string path = dir.file(l.name);
        write(path, l, 61, 37);
        if (l.name.starts_with("f32-zip")) {
            // These exercise the reader's own undoing of the floating-point predictor.
            TIFF* tif = TIFFOpen(path.c_str(), "r");
            ASSERT_TRUE(tif);
            uint16_t predictor = 0;
            TIFFGetFieldDefaulted(tif, TIFFTAG_PREDICTOR, &predictor);
            TIFFClose(tif);
            EXPECT_EQ(predictor, PREDICTOR_FLOATINGPOINT) << path;
        }
        expectSameAsOpenImageIO(path);
    }
}

TEST(RasterReaders, SampleImagesReadAsOpenImageIOReadsThem) {
    expectSameAsOpenImageIO(test::samplePath("bluemarble.png"));
    expectSameAsOpenImageIO(test::samplePath("srtm.png"));
    expectSameAsOpenImageIO(test::samplePath("dem.tif"));
}

} // namespace
} // namespace pyramid

// Computed bytes (BytePixels) read through a RasterSource: every read gives the same samples,
// for any channel range, and readUInt8 honours its row stride (rows stored bottom up here).
TEST(RasterReaders, ComputedBytesReadAlike) {
    class Gradient final : public pyramid::BytePixels {
    public:
        void readBytes(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out) const override {
            for (int y = y0; y < y1; ++y) {
                for (int x = x0; x < x1; ++x) {
                    for (int c = c0; c < c1; ++c) {
                        *out++ = value(x, y, c);
                    }
                }
            }
        }
        static uint8_t value(int x, int y, int c) { return static_cast<uint8_t>(x * 7 + y * 13 + c * 85); }
    };
    pyramid::RasterInfo info;
    info.width = 20;
    info.height = 10;
    info.channels = 3;
    info.type = pyramid::SampleType::UInt8;
    const auto source = pyramid::RasterSource::fromPixels("gradient", info, std::make_shared<Gradient>());
    const int x0 = 3, y0 = 2, x1 = 17, y1 = 9, w = x1 - x0, h = y1 - y0;
    for (int c0 = 0; c0 < 3; ++c0) {
        for (int c1 = c0 + 1; c1 <= 3; ++c1) {
            const int k = c1 - c0;
            std::vector<uint16_t> words(static_cast<size_t>(w * h * k));
            source->readUInt16(x0, y0, x1, y1, c0, c1, words.data());
            std::vector<uint8_t> bytes(static_cast<size_t>(w * h * k));
            // Bottom up: row y0 is the last row of the buffer.
            source->readUInt8(x0, y0, x1, y1, c0, c1, bytes.data() + static_cast<size_t>((h - 1) * w * k), -w * k);
            std::vector<float> floats(static_cast<size_t>(w * h));
            source->readFloat(x0, y0, x1, y1, c0, floats.data());
            for (int y = y0; y < y1; ++y) {
                for (int x = x0; x < x1; ++x) {
                    for (int c = c0; c < c1; ++c) {
                        const uint8_t want = Gradient::value(x, y, c);
                        const size_t at = static_cast<size_t>(((y - y0) * w + (x - x0)) * k + (c - c0));
                        const size_t up = static_cast<size_t>(((h - 1 - (y - y0)) * w + (x - x0)) * k + (c - c0));
                        ASSERT_EQ(words[at], want) << x << "," << y << "," << c;
                        ASSERT_EQ(bytes[up], want) << x << "," << y << "," << c;
                    }
                    ASSERT_EQ(floats[static_cast<size_t>((y - y0) * w + (x - x0))], Gradient::value(x, y, c0));
                }
            }
        }
    }
}

// Uncompressed striped TIFFs: narrow, tall windows (a pyramid's footprints) are copied from blocks
// of rows kept between reads, wide ones read row by row; both give the file's samples. Windows
// walk the image as a pyramid's subtrees do, north to south and west to east, on two threads at
// once, across the blocks' edges: rows long enough to be cut into columns (whose blocks pass the
// cache and are recycled), rows kept whole with strips stored in reverse order (so that rows
// following each other in the image do not in the file), 16-bit and float samples.
TEST(RasterReaders, UncompressedWindowsReadThroughBlocksGiveTheFilesSamples) {
    struct File {
        std::string name;
        int width, height, channels, bits;
        bool isFloat;
        int rowsPerStrip;
        bool reversed; // strips written last first
    };
    const std::vector<File> files = {
        {"wide-rgb8.tif", 12000, 720, 3, 8, false, 5, false},
        {"rgba16-reversed.tif", 700, 300, 4, 16, false, 3, true},
        {"f32x2.tif", 3000, 120, 2, 32, true, 7, false},
    };
    const auto value = [](const File& f, int x, int y, int c) -> uint32_t {
        const uint32_t v = static_cast<uint32_t>(x * 31 + y * 17 + c * 89 + (x * y) % 7);
        return f.bits == 8 ? v & 0xFFu : v & 0xFFFFu;
    };
    pyramid::test::TempDir dir;
    for (const File& f : files) {
        SCOPED_TRACE(f.name);
        const std::string path = dir.file(f.name);
        TIFF* tif = TIFFOpen(path.c_str(), "w");
        ASSERT_TRUE(tif);
        TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, f.width);
        TIFFSetField(tif, TIFFTAG_IMAGELENGTH, f.height);
        TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, f.channels);
        TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, f.bits);
        TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, f.isFloat ? SAMPLEFORMAT_IEEEFP : SAMPLEFORMAT_UINT);
        TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
        TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_NONE);
        TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, f.channels >= 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
        if (f.channels == 4 || f.channels == 2) {
            const uint16_t alpha = EXTRASAMPLE_UNASSALPHA;
            TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, 1, &alpha);
        }
        TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, f.rowsPerStrip);
        const int strips = (f.height + f.rowsPerStrip - 1) / f.rowsPerStrip;
        const size_t sampleBytes = static_cast<size_t>(f.bits / 8);
        for (int k = 0; k < strips; ++k) {
            const int s = f.reversed ? strips - 1 - k : k;
            const int rows = std::min(f.rowsPerStrip, f.height - s * f.rowsPerStrip);
            std::vector<uint8_t> strip(static_cast<size_t>(rows) * f.width * f.channels * sampleBytes);
            for (int y = 0; y < rows; ++y) {
                for (int x = 0; x < f.width; ++x) {
                    for (int c = 0; c < f.channels; ++c) {
                        const size_t at = ((static_cast<size_t>(y) * f.width + x) * f.channels + c) * sampleBytes;
                        const uint32_t v = value(f, x, s * f.rowsPerStrip + y, c);
                        if (f.isFloat) {
                            const float g = static_cast<float>(v);
                            std::memcpy(&strip[at], &g, 4);
                        } else if (f.bits == 16) {
                            const auto g = static_cast<uint16_t>(v);
                            std::memcpy(&strip[at], &g, 2);
                        } else {
                            strip[at] = static_cast<uint8_t>(v);
                        }
                    }
                }
            }
            ASSERT_GE(TIFFWriteEncodedStrip(tif, static_cast<uint32_t>(s), strip.data(),
                                            static_cast<tmsize_t>(strip.size())),
                      0);
        }
        TIFFClose(tif);
        const auto source = pyramid::RasterSource::open(path, 256);
        // Footprints (through blocks): 392 x 392 samples every 384 columns and rows in the wide
        // file, 97 x 97 every 90 in the others. Then a wide, short window and a narrow, short
        // one (row by row).
        const bool footprints = f.name == "wide-rgb8.tif";
        const int side = footprints ? 392 : 97, step = footprints ? 384 : 90;
        std::vector<std::array<int, 4>> windows;
        for (int y = 0; y < f.height; y += step) {
            for (int x = 0; x < f.width; x += step) {
                windows.push_back({x, y, std::min(f.width, x + side), std::min(f.height, y + side)});
            }
        }
        windows.push_back({5, 7, f.width - 3, 19}); // wide and short: row by row
        windows.push_back({1, 3, 40, 15});           // narrow but short: row by row
        std::atomic<int> wrong{0};
        const auto check = [&](size_t first) {
            for (size_t k = first; k < windows.size(); k += 2) {
                const auto [x0, y0, x1, y1] = windows[k];
                const int w = x1 - x0, h = y1 - y0, n = f.channels;
                if (f.isFloat) {
                    std::vector<float> got(static_cast<size_t>(w) * h);
                    source->readFloat(x0, y0, x1, y1, 1, got.data());
                    for (int y = 0; y < h; ++y) {
                        for (int x = 0; x < w; ++x) {
                            const float want = static_cast<float>(value(f, x0 + x, y0 + y, 1));
                            wrong += got[static_cast<size_t>(y) * w + x] != want;
                        }
                    }
                    continue;
                }
                // Every channel, and the last alone.
                std::vector<uint16_t> all(static_cast<size_t>(w) * h * n), last(static_cast<size_t>(w) * h);
                source->readUInt16(x0, y0, x1, y1, 0, n, all.data());
                source->readUInt16(x0, y0, x1, y1, n - 1, n, last.data());
                for (int y = 0; y < h; ++y) {
                    for (int x = 0; x < w; ++x) {
                        const size_t p = static_cast<size_t>(y) * w + x;
                        for (int c = 0; c < n; ++c) {
                            wrong += all[p * n + c] != value(f, x0 + x, y0 + y, c);
                        }
                        wrong += last[p] != value(f, x0 + x, y0 + y, n - 1);
                    }
                }
                if (f.bits == 8) {
                    // Bottom up through a negative stride, every channel and the middle one alone.
                    std::vector<uint8_t> bytes(static_cast<size_t>(w) * h * n), middle(static_cast<size_t>(w) * h);
                    source->readUInt8(x0, y0, x1, y1, 0, n, bytes.data() + static_cast<size_t>(h - 1) * w * n, -w * n);
                    source->readUInt8(x0, y0, x1, y1, 1, 2, middle.data() + static_cast<size_t>(h - 1) * w, -w);
                    for (int y = 0; y < h; ++y) {
                        for (int x = 0; x < w; ++x) {
                            const size_t up = static_cast<size_t>(h - 1 - y) * w + x;
                            for (int c = 0; c < n; ++c) {
                                wrong += bytes[up * n + c] != value(f, x0 + x, y0 + y, c);
                            }
                            wrong += middle[up] != value(f, x0 + x, y0 + y, 1);
                        }
                    }
                }
            }
        };
        std::atomic<int> failed{0};
        const auto run = [&](size_t first) {
            try {
                check(first);
            } catch (const std::exception& e) {
                ADD_FAILURE() << e.what();
                ++failed;
            }
        };
        std::thread other(run, 1);
        run(0);
        other.join();
        EXPECT_EQ(failed.load(), 0);
        EXPECT_EQ(wrong.load(), 0);
    }
}
