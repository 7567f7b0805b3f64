// Writes a mosaic for bench/mosaic_bench.sh: COLS x ROWS tiles of SIZE x SIZE float32 heights
// (Deflate, strips of 16 rows, geographic EPSG:4326, 3 arc-second pixels as SRTM's, adjacent),
// named tile_ROW_COL.tif, and the same heights stitched into one file, whole.tif (Deflate,
// 256-sample tiles). A benchmark's input generator, never run by the tests.
//
//   mosaic_tiles OUTDIR COLS ROWS SIZE
#include <geotiff/geotiff.h>
#include <geotiff/geovalues.h>
#include <geotiff/xtiffio.h>
#include <tiffio.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

constexpr double kStep = 1.0 / 1200.0; // degrees per pixel
constexpr double kWest = 6.0, kNorth = 47.0;

float heightAt(long x, long y) {
    const double u = static_cast<double>(x) * 0.002, v = static_cast<double>(y) * 0.003;
    return static_cast<float>(1500.0 + 800.0 * std::sin(u) * std::cos(v) + 120.0 * std::sin(7.0 * u + 3.0 * v) +
                              static_cast<double>((x * 7 + y * 13) % 17));
}

bool writeTile(const std::string& path, long x0, long y0, long w, long h, bool tiled) {
    TIFF* tif = XTIFFOpen(path.c_str(), "w8");
    if (!tif) {
        return false;
    }
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(w));
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(h));
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, uint16_t{1});
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, uint16_t{32});
    TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, uint16_t{SAMPLEFORMAT_IEEEFP});
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
    TIFFSetField(tif, TIFFTAG_PREDICTOR, PREDICTOR_FLOATINGPOINT);
    const double tie[6] = {0.0, 0.0, 0.0, kWest + static_cast<double>(x0) * kStep, kNorth - static_cast<double>(y0) * kStep, 0.0};
    const double scale[3] = {kStep, kStep, 0.0};
    TIFFSetField(tif, TIFFTAG_GEOTIEPOINTS, uint16_t{6}, tie);
    TIFFSetField(tif, TIFFTAG_GEOPIXELSCALE, uint16_t{3}, scale);
    GTIF* gtif = GTIFNew(tif);
    GTIFKeySet(gtif, GTModelTypeGeoKey, TYPE_SHORT, 1, ModelTypeGeographic);
    GTIFKeySet(gtif, GTRasterTypeGeoKey, TYPE_SHORT, 1, RasterPixelIsArea);
    GTIFKeySet(gtif, GeographicTypeGeoKey, TYPE_SHORT, 1, 4326);
    GTIFWriteKeys(gtif);
    GTIFFree(gtif);
    bool ok = true;
    if (tiled) {
        const long T = 256;
        TIFFSetField(tif, TIFFTAG_TILEWIDTH, static_cast<uint32_t>(T));
        TIFFSetField(tif, TIFFTAG_TILELENGTH, static_cast<uint32_t>(T));
        std::vector<float> block(static_cast<size_t>(T * T));
        for (long ty = 0; ty < h && ok; ty += T) {
            for (long tx = 0; tx < w && ok; tx += T) {
                for (long y = 0; y < T; ++y) {
                    for (long x = 0; x < T; ++x) {
                        block[static_cast<size_t>(y * T + x)] = (tx + x < w && ty + y < h) ? heightAt(x0 + tx + x, y0 + ty + y) : 0.0f;
                    }
                }
                ok = TIFFWriteEncodedTile(tif, TIFFComputeTile(tif, static_cast<uint32_t>(tx), static_cast<uint32_t>(ty), 0, 0),
                                          block.data(), static_cast<tmsize_t>(block.size() * 4)) >= 0;
            }
        }
    } else {
        const long rows = 16;
        TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, static_cast<uint32_t>(rows));
        std::vector<float> strip(static_cast<size_t>(w * rows));
        for (long s0 = 0; s0 < h && ok; s0 += rows) {
            const long n = std::min(rows, h - s0);
            for (long y = 0; y < n; ++y) {
                for (long x = 0; x < w; ++x) {
                    strip[static_cast<size_t>(y * w + x)] = heightAt(x0 + x, y0 + s0 + y);
                }
            }
            ok = TIFFWriteEncodedStrip(tif, TIFFComputeStrip(tif, static_cast<uint32_t>(s0), 0), strip.data(),
                                       static_cast<tmsize_t>(static_cast<size_t>(w * n) * 4)) >= 0;
        }
    }
    XTIFFClose(tif);
    return ok;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 5) {
        std::fprintf(stderr, "usage: %s OUTDIR COLS ROWS SIZE\n", argv[0]);
        return 2;
    }
    const std::string dir = argv[1];
    const long cols = std::atol(argv[2]), rows = std::atol(argv[3]), size = std::atol(argv[4]);
    if (cols < 1 || rows < 1 || size < 2) {
        std::fprintf(stderr, "%s: COLS, ROWS >= 1 and SIZE >= 2\n", argv[0]);
        return 2;
    }
    for (long r = 0; r < rows; ++r) {
        for (long c = 0; c < cols; ++c) {
            char name[64];
            std::snprintf(name, sizeof name, "/tile_%03ld_%03ld.tif", r, c);
            if (!writeTile(dir + name, c * size, r * size, size, size, false)) {
                std::fprintf(stderr, "%s: cannot write %s%s\n", argv[0], dir.c_str(), name);
                return 1;
            }
        }
    }
    if (!writeTile(dir + "/whole.tif", 0, 0, cols * size, rows * size, true)) {
        std::fprintf(stderr, "%s: cannot write %s/whole.tif\n", argv[0], dir.c_str());
        return 1;
    }
    return 0;
}
