// Rewrites a single-band float32 TIFF (as dem_synthetic_heights writes it) in the layouts real
// DEMs ship in, for the input benchmarks (bench/input_bench.sh) and by hand:
//
//   tiff_layouts INPUT.tif OUTPUT.tif LAYOUT
//
// LAYOUT: tiled-deflate-p3 (256 x 256 tiles, Deflate, floating-point predictor: a COG's),
// lzw-strips (LZW, 16 rows per strip, floating-point predictor), deflate-rows (Deflate strips of
// one row), zstd-tiled (512 x 512 tiles), bigtiff-tiled (BigTIFF, 256 x 256 Deflate tiles),
// int16-deflate (heights rounded to int16, 256 x 256 tiles, horizontal predictor), one-strip
// (Deflate, the whole image in a single strip); and ESRI's grids, which are no TIFFs:
// ascii-grid (OUTPUT.asc, each float32 in the 9 digits that give it back) and bil (OUTPUT.bil,
// float32 little-endian, with OUTPUT.hdr beside it).
#include <tiffio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct Layout {
    bool tiled = false;
    uint32_t block = 256;   // tile side, or rows per strip
    uint16_t compression = COMPRESSION_ADOBE_DEFLATE;
    uint16_t predictor = PREDICTOR_NONE;
    bool bigtiff = false;
    bool int16 = false;
};

bool layoutNamed(const std::string& name, uint32_t height, Layout& l) {
    if (name == "tiled-deflate-p3") {
        l = {true, 256, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_FLOATINGPOINT, false, false};
    } else if (name == "lzw-strips") {
        l = {false, 16, COMPRESSION_LZW, PREDICTOR_FLOATINGPOINT, false, false};
    } else if (name == "deflate-rows") {
        l = {false, 1, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, false, false};
    } else if (name == "zstd-tiled") {
        l = {true, 512, COMPRESSION_ZSTD, PREDICTOR_FLOATINGPOINT, false, false};
    } else if (name == "bigtiff-tiled") {
        l = {true, 256, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_FLOATINGPOINT, true, false};
    } else if (name == "int16-deflate") {
        l = {true, 256, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_HORIZONTAL, false, true};
    } else if (name == "one-strip") {
        l = {false, height, COMPRESSION_ADOBE_DEFLATE, PREDICTOR_NONE, false, false};
    } else {
        return false;
    }
    return true;
}

// ESRI's grids of the input's rows, 1 m cells: a text of the values, or their bytes with a .hdr.
int writeEsriGrid(TIFF* in, uint32_t width, uint32_t height, const std::string& path, bool ascii) {
    FILE* out = std::fopen(path.c_str(), "wb");
    if (!out) {
        return 1;
    }
    if (ascii) {
        std::fprintf(out, "ncols %u\nnrows %u\nxllcorner 0\nyllcorner 0\ncellsize 1\n", width, height);
    } else {
        const std::string hdr = path.substr(0, path.size() - 4) + ".hdr";
        FILE* h = std::fopen(hdr.c_str(), "wb");
        if (!h) {
            return 1;
        }
        std::fprintf(h, "BYTEORDER I\nLAYOUT BIL\nNROWS %u\nNCOLS %u\nNBITS 32\nPIXELTYPE FLOAT\n", height, width);
        std::fclose(h);
    }
    std::vector<float> row(width);
    for (uint32_t y = 0; y < height; ++y) {
        if (TIFFReadScanline(in, row.data(), y) < 0) {
            return 1;
        }
        if (!ascii) {
            std::fwrite(row.data(), 4, width, out);
            continue;
        }
        for (uint32_t x = 0; x < width; ++x) {
            std::fprintf(out, x + 1 < width ? "%.9g " : "%.9g\n", static_cast<double>(row[x]));
        }
    }
    return std::fclose(out) == 0 ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: %s INPUT.tif OUTPUT.tif LAYOUT\n", argv[0]);
        return 2;
    }
    TIFF* in = TIFFOpen(argv[1], "r");
    if (!in) {
        return 1;
    }
    uint32_t width = 0, height = 0;
    uint16_t bits = 0, format = 0;
    TIFFGetField(in, TIFFTAG_IMAGEWIDTH, &width);
    TIFFGetField(in, TIFFTAG_IMAGELENGTH, &height);
    TIFFGetFieldDefaulted(in, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetFieldDefaulted(in, TIFFTAG_SAMPLEFORMAT, &format);
    if (bits != 32 || format != SAMPLEFORMAT_IEEEFP || TIFFIsTiled(in)) {
        std::fprintf(stderr, "%s: not a striped float32 TIFF\n", argv[1]);
        return 1;
    }
    if (std::string(argv[3]) == "ascii-grid" || std::string(argv[3]) == "bil") {
        const int rc = writeEsriGrid(in, width, height, argv[2], std::string(argv[3]) == "ascii-grid");
        TIFFClose(in);
        return rc;
    }
    Layout l;
    if (!layoutNamed(argv[3], height, l)) {
        std::fprintf(stderr, "%s: unknown layout\n", argv[3]);
        return 2;
    }
    TIFF* out = TIFFOpen(argv[2], l.bigtiff ? "w8" : "w");
    if (!out) {
        return 1;
    }
    const uint16_t sampleBits = l.int16 ? 16 : 32;
    TIFFSetField(out, TIFFTAG_IMAGEWIDTH, width);
    TIFFSetField(out, TIFFTAG_IMAGELENGTH, height);
    TIFFSetField(out, TIFFTAG_BITSPERSAMPLE, sampleBits);
    TIFFSetField(out, TIFFTAG_SAMPLEFORMAT, l.int16 ? SAMPLEFORMAT_INT : SAMPLEFORMAT_IEEEFP);
    TIFFSetField(out, TIFFTAG_SAMPLESPERPIXEL, uint16_t{1});
    TIFFSetField(out, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(out, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(out, TIFFTAG_COMPRESSION, l.compression);
    if (l.predictor != PREDICTOR_NONE) {
        TIFFSetField(out, TIFFTAG_PREDICTOR, l.predictor);
    }
    // Rows of blocks are read from the input a band at a time: memory stays one band.
    const uint32_t band = l.tiled ? l.block : std::min(l.block, height);
    if (l.tiled) {
        TIFFSetField(out, TIFFTAG_TILEWIDTH, l.block);
        TIFFSetField(out, TIFFTAG_TILELENGTH, l.block);
    } else {
        TIFFSetField(out, TIFFTAG_ROWSPERSTRIP, band);
    }
    const size_t sampleBytes = sampleBits / 8;
    std::vector<float> rows(static_cast<size_t>(width) * band);
    std::vector<uint8_t> block;
    for (uint32_t y0 = 0; y0 < height; y0 += band) {
        const uint32_t n = std::min(band, height - y0);
        for (uint32_t r = 0; r < n; ++r) {
            if (TIFFReadScanline(in, rows.data() + static_cast<size_t>(r) * width, y0 + r) < 0) {
                return 1;
            }
        }
        const auto put = [&](size_t k, uint8_t* to) {
            if (l.int16) {
                const auto v = static_cast<int16_t>(std::lround(std::clamp(rows[k], -32768.0f, 32767.0f)));
                std::memcpy(to, &v, 2);
            } else {
                std::memcpy(to, &rows[k], 4);
            }
        };
        if (l.tiled) {
            block.assign(static_cast<size_t>(l.block) * l.block * sampleBytes, 0);
            for (uint32_t x0 = 0; x0 < width; x0 += l.block) {
                std::fill(block.begin(), block.end(), uint8_t{0});
                for (uint32_t r = 0; r < n; ++r) {
                    for (uint32_t c = 0; c < l.block && x0 + c < width; ++c) {
                        put(static_cast<size_t>(r) * width + x0 + c,
                            block.data() + (static_cast<size_t>(r) * l.block + c) * sampleBytes);
                    }
                }
                if (TIFFWriteEncodedTile(out, TIFFComputeTile(out, x0, y0, 0, 0), block.data(),
                                         static_cast<tmsize_t>(block.size())) < 0) {
                    return 1;
                }
            }
        } else {
            block.resize(static_cast<size_t>(width) * n * sampleBytes);
            for (size_t k = 0; k < static_cast<size_t>(width) * n; ++k) {
                put(k, block.data() + k * sampleBytes);
            }
            if (TIFFWriteEncodedStrip(out, TIFFComputeStrip(out, y0, 0), block.data(),
                                      static_cast<tmsize_t>(block.size())) < 0) {
                return 1;
            }
        }
    }
    TIFFClose(in);
    TIFFClose(out);
    return 0;
}
