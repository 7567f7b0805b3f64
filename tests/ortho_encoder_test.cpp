// preprocessOrtho as a library, the levels' pixels: lossless levels equal the input and the exact
// averages (sRGB averages light), uncompressed TIFF inputs give the PNG's files, 16-bit input
// rounds to 8 bits, and resampled pixels are the documented bilinear formula.
#include <gtest/gtest.h>
#include <tiffio.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "formats/ortho_file.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_levels.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/verify/ortho_verify.hpp"
#include "tests/support/ortho_images.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::orthoImage;
using test::smallOrtho;

TEST(OrthoEncoder, LosslessLevelsAreTheInputAndItsAverages) {
    test::TempDir dir;
    const int W = 64; // 16 << 2: pixel exact, levels 0..2
    const auto px = orthoImage(W, W, 3, 250);
    test::writeImage(dir.file("in.png"), W, W, 3, px, false);
    OrthoEncodeOptions o = smallOrtho();
    o.levels.colourSpace = ColourSpace::Linear;
    o.writeDxt = o.writeResiduals = false;
    const OrthoReport report = encodeOrtho(dir.file("in.png"), dir.file("out"), o);
    EXPECT_EQ(report.maxLevel, 2);
    EXPECT_EQ(report.sampling, "input pixels are the finest level's pixels (no resampling)");
    const auto reader = OrthoFileReader::open(dir.file("out/RGB.dat"));
    EXPECT_EQ(reader->header().flags, 0u);
    EXPECT_EQ(reader->header().tilePixels(), 20);
    auto input = [&](int x, int y, int c) { // pyramid coordinates, clamped at the edges
        x = std::clamp(x, 0, W - 1);
        y = std::clamp(y, 0, W - 1);
        return static_cast<int>(px[(static_cast<size_t>(W - 1 - y) * W + x) * 3 + c]);
    };
    // Finest level: tile (2, 1, 2) pixel (i, j) is input pixel (16 + i - 2, 32 + j - 2).
    const auto fine = reader->readTile(2, 1, 2);
    for (int j = 0; j < 20; ++j) {
        for (int i = 0; i < 20; ++i) {
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(fine[(static_cast<size_t>(j) * 20 + i) * 3 + c], input(16 + i - 2, 32 + j - 2, c));
            }
        }
    }
    // Level 1 pixel (x, y) of the level = (sum of the 2x2 input block + 2) / 4.
    const auto mid = reader->readTile(1, 0, 1);
    for (int j = 2; j < 18; ++j) {
        for (int i = 2; i < 18; ++i) {
            const int x = i - 2, y = 16 + j - 2;
            for (int c = 0; c < 3; ++c) {
                const int sum = input(2 * x, 2 * y, c) + input(2 * x + 1, 2 * y, c) + input(2 * x, 2 * y + 1, c) +
                                input(2 * x + 1, 2 * y + 1, c);
                ASSERT_EQ(mid[(static_cast<size_t>(j) * 20 + i) * 3 + c], (sum + 2) / 4);
            }
        }
    }
    OrthoVerifyOptions vo;
    vo.colourSpace = ColourSpace::Linear;
    EXPECT_TRUE(verifyOrtho(dir.file("out/RGB.dat"), dir.file("in.png"), vo).ok);
}

// Uncompressed striped TIFF inputs are read directly from the file (tiff_pixel_reader.hpp),
// other inputs through OpenImageIO: the same pixels give the same files, byte for byte, pixel
// exact or resampled, with all three outputs.
// The tiles fitted to a longer side: the fewest levels of tiles of at most 256 pixels, then the
// smallest multiple of 4 that holds it.
TEST(OrthoEncoder, FittedTilesHoldTheLongerSideWithTheLeastResampling) {
    const std::vector<std::tuple<int64_t, int, int>> cases = {
        {1, 4, 0},       {256, 256, 0},  {257, 132, 1},  {300, 152, 1},   {1350, 172, 3},
        {2700, 172, 4},  {4096, 256, 4}, {6144, 192, 5}, {21600, 172, 7}, {86400, 172, 9}};
    for (const auto& [side, tileSize, maxLevel] : cases) {
        const OrthoTileFit fit = fitOrthoTiles(side);
        EXPECT_EQ(fit.tileSize, tileSize) << side;
        EXPECT_EQ(fit.maxLevel, maxLevel) << side;
        EXPECT_GE(static_cast<int64_t>(fit.tileSize) << fit.maxLevel, side);
        EXPECT_LT((static_cast<int64_t>(fit.tileSize) << fit.maxLevel) - side, int64_t{4} << fit.maxLevel);
    }
}

TEST(OrthoEncoder, UncompressedTiffInputGivesTheSameFilesAsPng) {
    for (const auto& [w, h] : {std::pair{64, 64}, std::pair{50, 30}}) {
        SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
        test::TempDir dir;
        const auto px = orthoImage(w, h, 3, 250);
        test::writeImage(dir.file("in.png"), w, h, 3, px, false);
        TIFF* t = TIFFOpen(dir.file("in.tif").c_str(), "w");
        ASSERT_NE(t, nullptr);
        TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(w));
        TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(h));
        TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 8);
        TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 3);
        TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
        TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_RGB);
        TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_NONE);
        TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, 7u); // rows of a window span strips
        std::vector<uint8_t> row(static_cast<size_t>(w) * 3);
        for (int y = 0; y < h; ++y) {
            std::copy_n(px.begin() + static_cast<std::ptrdiff_t>(y) * w * 3, row.size(), row.begin());
            ASSERT_EQ(TIFFWriteScanline(t, row.data(), static_cast<uint32_t>(y), 0), 1);
        }
        TIFFClose(t);
        OrthoEncodeOptions o = smallOrtho();
        o.levels.threads = 2;
        encodeOrtho(dir.file("in.png"), dir.file("png"), o);
        encodeOrtho(dir.file("in.tif"), dir.file("tif"), o);
        for (const char* f : {"RGB.dat", "dxt/RGB.dat", "residuals/RGB.dat"}) {
            SCOPED_TRACE(f);
            std::ifstream a(dir.file(std::string("png/") + f), std::ios::binary);
            std::ifstream b(dir.file(std::string("tif/") + f), std::ios::binary);
            const std::string bytesA((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>());
            const std::string bytesB((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
            EXPECT_FALSE(bytesA.empty());
            EXPECT_TRUE(bytesA == bytesB);
        }
    }
}

TEST(OrthoEncoder, SrgbAveragesLight) {
    test::TempDir dir;
    // Black and white stripes: the sRGB average of 0 and 255 is 188, not 128.
    std::vector<uint16_t> px(32 * 32);
    for (int y = 0; y < 32; ++y) {
        for (int x = 0; x < 32; ++x) {
            px[static_cast<size_t>(y * 32 + x)] = (x % 2) ? 255 : 0;
        }
    }
    test::writeImage(dir.file("stripes.png"), 32, 32, 1, px, false);
    OrthoEncodeOptions o = smallOrtho();
    o.writeDxt = o.writeResiduals = false;
    encodeOrtho(dir.file("stripes.png"), dir.file("out"), o);
    const auto root = OrthoFileReader::open(dir.file("out/RGB.dat"))->readTile(0, 0, 0);
    EXPECT_EQ(root[5 + 5 * 20], 188);
}

TEST(OrthoEncoder, SixteenBitInputRoundsToEightBits) {
    test::TempDir dir;
    const auto px = orthoImage(32, 32, 1, 65000);
    test::writeImage(dir.file("in16.tif"), 32, 32, 1, px, true);
    OrthoEncodeOptions o = smallOrtho();
    o.writeDxt = o.writeResiduals = false;
    encodeOrtho(dir.file("in16.tif"), dir.file("out"), o);
    const auto fine = OrthoFileReader::open(dir.file("out/RGB.dat"))->readTile(1, 0, 0);
    // Tile (1,0,0) pixel (i, j) is input pixel (i - 2, 31 - (j - 2)).
    for (int j = 2; j < 18; ++j) {
        for (int i = 2; i < 18; ++i) {
            const int v16 = px[static_cast<size_t>((31 - (j - 2)) * 32 + (i - 2))];
            ASSERT_EQ(fine[static_cast<size_t>(j * 20 + i)], static_cast<int>(std::lround(v16 * 255.0 / 65535.0)));
        }
    }
}

// The documented resampling (ortho_levels.hpp), pixel by pixel: finest pixel x's centre lies at
// input position X = (x + 0.5) * scale - 0.5 (rows counted from the north), bilinear between the
// clamped neighbours in double precision, then v * 255 / full rounded half up; 0 beyond the input.
uint8_t referencePixel(const std::vector<uint16_t>& in, int w, int h, int channels, int full, double sx, double sy,
                       int64_t W, int64_t x, int64_t y, int c) {
    const double X = (static_cast<double>(x) + 0.5) * sx - 0.5;
    const double Y = (static_cast<double>(W - 1 - y) + 0.5) * sy - 0.5;
    if (X > w - 0.5 || Y > h - 0.5) {
        return 0;
    }
    const double fx = X - std::floor(X), fy = Y - std::floor(Y);
    const int c0 = std::clamp(static_cast<int>(std::floor(X)), 0, w - 1), c1 = std::clamp(static_cast<int>(std::floor(X)) + 1, 0, w - 1);
    const int r0 = std::clamp(static_cast<int>(std::floor(Y)), 0, h - 1), r1 = std::clamp(static_cast<int>(std::floor(Y)) + 1, 0, h - 1);
    const auto v = [&](int col, int row) { return static_cast<double>(in[(static_cast<size_t>(row) * w + col) * channels + c]); };
    const double top = v(c0, r0) + (v(c1, r0) - v(c0, r0)) * fx;
    const double bottom = v(c0, r1) + (v(c1, r1) - v(c0, r1)) * fx;
    const double x8 = (top + (bottom - top) * fy) * 255.0 / full;
    return static_cast<uint8_t>(std::floor(x8) + (x8 - std::floor(x8) >= 0.5 ? 1 : 0));
}

TEST(OrthoEncoder, ResampledPixelsAreTheBilinearFormula) {
    const int w = 50, h = 30, T = 16, W = 64; // finest level 2: 64 x 64 pixels, resampled
    for (const int channels : {1, 3, 4}) {
        for (const bool sixteen : {false, true}) {
            for (const bool stretch : {false, true}) {
                SCOPED_TRACE(std::to_string(channels) + " channels, " + (sixteen ? "16" : "8") + " bits" +
                             (stretch ? ", stretched" : ""));
                test::TempDir dir;
                const int full = sixteen ? 65535 : 255;
                test::writeImage(dir.file("in.png"), w, h, channels, orthoImage(w, h, channels, full - 8), sixteen);
                // The samples as stored (the PNG writer may have un-premultiplied an alpha channel).
                std::vector<uint16_t> px(static_cast<size_t>(w) * h * channels);
                RasterSource::open(dir.file("in.png"))->readUInt16(0, 0, w, h, 0, channels, px.data());
                OrthoEncodeOptions o = smallOrtho();
                o.levels.stretch = stretch;
                o.writeDxt = o.writeResiduals = false;
                encodeOrtho(dir.file("in.png"), dir.file("out"), o);
                const auto reader = OrthoFileReader::open(dir.file("out/RGB.dat"));
                ASSERT_EQ(reader->header().maxLevel, 2);
                const double sx = (stretch ? w : std::max(w, h)) / static_cast<double>(W);
                const double sy = (stretch ? h : std::max(w, h)) / static_cast<double>(W);
                for (int ty = 0; ty < 4; ++ty) {
                    for (int tx = 0; tx < 4; ++tx) {
                        const auto tile = reader->readTile(2, tx, ty);
                        for (int j = 2; j < T + 2; ++j) {
                            for (int i = 2; i < T + 2; ++i) {
                                for (int c = 0; c < channels; ++c) {
                                    const int64_t x = tx * T + i - 2, y = ty * T + j - 2;
                                    ASSERT_EQ(tile[static_cast<size_t>((j * (T + 4) + i) * channels + c)],
                                              referencePixel(px, w, h, channels, full, sx, sy, W, x, y, c))
                                        << "pixel " << x << "," << y << " channel " << c;
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

} // namespace
} // namespace pyramid
