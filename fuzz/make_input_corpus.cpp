// Writes the seed inputs of raster_input_fuzz into tests/corpus/input/: small valid rasters in
// every layout the input readers take, for the fuzzer to mutate. Deterministic; run by hand
// after changing it:
//   g++ -std=c++20 fuzz/make_input_corpus.cpp -o /tmp/make_input_corpus -ltiff -lpng -ljpeg
//   /tmp/make_input_corpus tests/corpus/input
#include <png.h>
#include <tiffio.h>

#include <cstdint>
#include <cstdio>
// jpeglib.h needs FILE and size_t declared first.
#include <jpeglib.h>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr uint32_t kWidth = 40, kHeight = 24;
// One-strip images are larger: 300 x 240 samples decode to 288 KB, more than a quarter of the
// fuzzer's 1 MB cache, so that they go through the strip stream and the scratch file.
constexpr uint32_t kStripWidth = 300, kStripHeight = 240;

struct Tiff {
    const char* name;
    uint16_t bits, format, compression, predictor;
    uint32_t tile, rowsPerStrip; // rowsPerStrip 0: the whole image in one strip
    const char* mode;
    uint16_t channels = 1; // RGB from 3
    bool separate = false; // bands in separate planes (else interleaved)
    bool palette = false;  // 8-bit indices into a colour map
};

bool writeTiff(const std::string& dir, const Tiff& l) {
    TIFF* t = TIFFOpen((dir + "/" + l.name).c_str(), l.mode);
    if (!t) {
        return false;
    }
    const bool oneStrip = l.tile == 0 && l.rowsPerStrip == 0;
    const uint32_t width = oneStrip ? kStripWidth : kWidth, height = oneStrip ? kStripHeight : kHeight;
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, width);
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, height);
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, l.bits);
    TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, l.format);
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, l.channels);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC,
                 l.palette ? PHOTOMETRIC_PALETTE : l.channels >= 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
    if (l.channels > 1) {
        TIFFSetField(t, TIFFTAG_PLANARCONFIG, l.separate ? PLANARCONFIG_SEPARATE : PLANARCONFIG_CONTIG);
    }
    std::vector<uint16_t> map(3 * 256);
    if (l.palette) {
        for (size_t k = 0; k < map.size(); ++k) {
            map[k] = static_cast<uint16_t>(k * 2654435761u >> 16);
        }
        TIFFSetField(t, TIFFTAG_COLORMAP, map.data(), map.data() + 256, map.data() + 512);
    }
    TIFFSetField(t, TIFFTAG_COMPRESSION, l.compression);
    if (l.predictor != PREDICTOR_NONE) {
        TIFFSetField(t, TIFFTAG_PREDICTOR, l.predictor);
    }
    const size_t sampleBytes = l.bits / 8u;
    const uint16_t planes = l.separate ? l.channels : 1, perPixel = l.channels / planes;
    const size_t bytes = sampleBytes * perPixel; // of a pixel in a block
    uint16_t plane = 0;                          // the plane being written (separate planes)
    const auto sample = [&](uint32_t x, uint32_t y, uint8_t* pixel) {
        for (uint32_t k = 0; k < perPixel; ++k) {
            const uint32_t c = l.separate ? plane : k;
            uint8_t* to = pixel + k * sampleBytes;
            const double v = static_cast<double>((x * 37 + y * 101 + c * 53) % 997) - 300.0;
            if (l.format == SAMPLEFORMAT_IEEEFP && l.bits == 64) {
                const double d = v / 3.0;
                std::memcpy(to, &d, 8);
            } else if (l.format == SAMPLEFORMAT_IEEEFP) {
                const auto f = static_cast<float>(v * 0.5);
                std::memcpy(to, &f, 4);
            } else if (sampleBytes == 2) {
                const auto s = static_cast<int16_t>(v);
                std::memcpy(to, &s, 2);
            } else {
                to[0] = static_cast<uint8_t>(static_cast<int>(v) & 0xff);
            }
        }
    };
    const uint32_t tile = l.tile, rows = oneStrip ? height : l.rowsPerStrip;
    if (tile) {
        TIFFSetField(t, TIFFTAG_TILEWIDTH, tile);
        TIFFSetField(t, TIFFTAG_TILELENGTH, tile);
        std::vector<uint8_t> block(static_cast<size_t>(tile) * tile * bytes);
        for (plane = 0; plane < planes; ++plane) {
            for (uint32_t ty = 0; ty < height; ty += tile) {
                for (uint32_t tx = 0; tx < width; tx += tile) {
                    std::memset(block.data(), 0, block.size());
                    for (uint32_t y = ty; y < ty + tile && y < height; ++y) {
                        for (uint32_t x = tx; x < tx + tile && x < width; ++x) {
                            sample(x, y, block.data() + ((y - ty) * tile + (x - tx)) * bytes);
                        }
                    }
                    TIFFWriteEncodedTile(t, TIFFComputeTile(t, tx, ty, 0, plane), block.data(),
                                         static_cast<tmsize_t>(block.size()));
                }
            }
        }
    } else {
        TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, rows);
        for (plane = 0; plane < planes; ++plane) {
            for (uint32_t y0 = 0; y0 < height; y0 += rows) {
                const uint32_t n = y0 + rows <= height ? rows : height - y0;
                std::vector<uint8_t> strip(static_cast<size_t>(width) * n * bytes);
                for (uint32_t y = y0; y < y0 + n; ++y) {
                    for (uint32_t x = 0; x < width; ++x) {
                        sample(x, y, strip.data() + ((y - y0) * width + x) * bytes);
                    }
                }
                TIFFWriteEncodedStrip(t, TIFFComputeStrip(t, y0, plane), strip.data(),
                                      static_cast<tmsize_t>(strip.size()));
            }
        }
    }
    TIFFClose(t);
    return true;
}

// Appends to the TIFF `name` an internal transparency mask of its first image (kWidth x kHeight),
// as GDAL writes one: NewSubfileType 4, 1-bit samples, Deflate, in tiles of `tile`.
bool appendMask(const std::string& dir, const char* name, uint32_t tile) {
    TIFF* t = TIFFOpen((dir + "/" + name).c_str(), "a");
    if (!t) {
        return false;
    }
    TIFFSetField(t, TIFFTAG_SUBFILETYPE, FILETYPE_MASK);
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, kWidth);
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, kHeight);
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 1);
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MASK);
    TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
    TIFFSetField(t, TIFFTAG_TILEWIDTH, tile);
    TIFFSetField(t, TIFFTAG_TILELENGTH, tile);
    std::vector<uint8_t> block(static_cast<size_t>(tile / 8) * tile);
    for (uint32_t ty = 0; ty < kHeight; ty += tile) {
        for (uint32_t tx = 0; tx < kWidth; tx += tile) {
            for (size_t k = 0; k < block.size(); ++k) {
                block[k] = static_cast<uint8_t>((k + tx) * 2654435761u >> 24); // some pixels masked
            }
            TIFFWriteEncodedTile(t, TIFFComputeTile(t, tx, ty, 0, 0), block.data(), static_cast<tmsize_t>(block.size()));
        }
    }
    TIFFClose(t);
    return true;
}

// A PNG of `channels` samples of `depth` bits a pixel (a palette's index: `channels` 1), with a
// transparency chunk for a palette or grey image when `transparent`.
bool writePng(const std::string& dir, const char* name, int depth, int colour, int channels, bool interlaced,
              bool transparent = false) {
    std::FILE* f = std::fopen((dir + "/" + name).c_str(), "wb");
    if (!f) {
        return false;
    }
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, kWidth, kHeight, depth, colour, interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    std::vector<png_color> palette(static_cast<size_t>(1) << depth);
    std::vector<png_byte> alphas(palette.size());
    for (size_t k = 0; k < palette.size(); ++k) {
        palette[k] = {static_cast<png_byte>(k * 7), static_cast<png_byte>(255 - k), static_cast<png_byte>(k * k)};
        alphas[k] = static_cast<png_byte>(k * 31);
    }
    if (colour == PNG_COLOR_TYPE_PALETTE) {
        png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
    }
    png_color_16 key{};
    key.gray = 1;
    if (transparent) {
        png_set_tRNS(png, info, alphas.data(), colour == PNG_COLOR_TYPE_PALETTE ? static_cast<int>(alphas.size()) : 0,
                     &key);
    }
    png_write_info(png, info);
    const size_t rowBytes = (static_cast<size_t>(kWidth) * channels * depth + 7) / 8;
    std::vector<uint8_t> image(rowBytes * kHeight);
    for (size_t k = 0; k < image.size(); ++k) {
        image[k] = static_cast<uint8_t>((k * 2654435761u) >> 24);
    }
    std::vector<png_bytep> rows(kHeight);
    for (uint32_t y = 0; y < kHeight; ++y) {
        rows[y] = image.data() + y * rowBytes;
    }
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    return true;
}

} // namespace

// A JPEG file of `components` (1: grey, 3: YCbCr with 2 x 2 chroma), baseline or progressive.
bool writeJpeg(const std::string& dir, const char* name, int components, bool progressive) {
    FILE* f = std::fopen((dir + "/" + name).c_str(), "wb");
    if (!f) {
        return false;
    }
    jpeg_compress_struct c{};
    jpeg_error_mgr errors{};
    c.err = jpeg_std_error(&errors);
    jpeg_create_compress(&c);
    jpeg_stdio_dest(&c, f);
    c.image_width = kWidth;
    c.image_height = kHeight;
    c.input_components = components;
    c.in_color_space = components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 80, TRUE);
    if (progressive) {
        jpeg_simple_progression(&c);
    }
    jpeg_start_compress(&c, TRUE);
    std::vector<uint8_t> row(kWidth * static_cast<uint32_t>(components));
    for (uint32_t y = 0; y < kHeight; ++y) {
        for (size_t k = 0; k < row.size(); ++k) {
            row[k] = static_cast<uint8_t>(k * 5 + y * 11);
        }
        JSAMPROW rows[1] = {row.data()};
        jpeg_write_scanlines(&c, rows, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    return std::fclose(f) == 0;
}

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s DIRECTORY\n", argv[0]);
        return 2;
    }
    const std::string dir = argv[1];
    const Tiff tiffs[] = {
        {"f32-deflate-p3-tiled.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_FLOATINGPOINT, 16, 0, "w"},
        {"f32-lzw-p3-strips.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_LZW, PREDICTOR_FLOATINGPOINT, 0, 5, "w"},
        {"f32-deflate-rows.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 0, 1, "w"},
        {"f32-deflate-one-strip-be.tif", 32, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 0, 0, "wb"},
        {"i16-deflate-p2-one-strip.tif", 16, SAMPLEFORMAT_INT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 0, 0, "w"},
        {"i16-bigtiff-tiled.tif", 16, SAMPLEFORMAT_INT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 16, 0, "w8"},
        {"u8-packbits-strips.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_PACKBITS, PREDICTOR_NONE, 0, 7, "w"},
        {"u16-none-one-strip.tif", 16, SAMPLEFORMAT_UINT, COMPRESSION_NONE, PREDICTOR_NONE, 0, 0, "w"},
        {"rgb8-deflate-p2-tiled.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 16, 0, "w", 3},
        {"rgba16-deflate-p2-one-strip-be.tif", 16, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, 0, 0, "wb", 4},
        {"rgb8-planes-deflate-tiled.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 16, 0, "w", 3, true},
        {"rgba16-planes-lzw-strips-be.tif", 16, SAMPLEFORMAT_UINT, COMPRESSION_LZW, PREDICTOR_HORIZONTAL, 0, 5, "wb", 4, true},
        {"palette-deflate-tiled.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 16, 0, "w", 1, false, true},
        {"f64-deflate-p3-tiled.tif", 64, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_FLOATINGPOINT, 16, 0, "w"},
        {"f64-deflate-one-strip.tif", 64, SAMPLEFORMAT_IEEEFP, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 0, 0, "w"},
        {"rgb8-mask-tiled.tif", 8, SAMPLEFORMAT_UINT, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, 16, 0, "w", 3},
    };
    bool ok = true;
    for (const Tiff& t : tiffs) {
        ok = writeTiff(dir, t) && ok;
    }
    ok = appendMask(dir, "rgb8-mask-tiled.tif", 16) && ok;
    ok = writePng(dir, "grey16.png", 16, PNG_COLOR_TYPE_GRAY, 1, false) && ok;
    ok = writePng(dir, "rgb8.png", 8, PNG_COLOR_TYPE_RGB, 3, false) && ok;
    ok = writePng(dir, "rgba8-interlaced.png", 8, PNG_COLOR_TYPE_RGB_ALPHA, 4, true) && ok;
    ok = writePng(dir, "palette8-alpha.png", 8, PNG_COLOR_TYPE_PALETTE, 1, false, true) && ok;
    ok = writePng(dir, "grey2-key-interlaced.png", 2, PNG_COLOR_TYPE_GRAY, 1, true, true) && ok;
    ok = writeJpeg(dir, "grey.jpg", 1, false) && ok;
    ok = writeJpeg(dir, "ycbcr-progressive.jpg", 3, true) && ok;
    return ok ? 0 : 1;
}
