// preprocessOrtho as a library: lossless levels equal the input and the exact averages, DXT
// within its error, colour residuals rebuilt bit for bit by the CPU producer, determinism,
// borders, 16-bit input.
#include <gtest/gtest.h>
#include <tiffio.h>

#include <fstream>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <tuple>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_levels.hpp"
#include "libpyramid/encode/ortho/ortho_tile_encoder.hpp"
#include "libpyramid/filters/colour_upsample.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/verify/ortho_verify.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

// A smooth colour image with some texture, row 0 = north.
std::vector<uint16_t> image(int w, int h, int channels, int maxValue) {
    std::vector<uint16_t> v(static_cast<size_t>(w) * h * channels);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < channels; ++c) {
                const double s = 0.5 + 0.45 * std::sin(x / (7.0 + c) + y / 11.0) * std::cos((x - y) / 13.0);
                v[(static_cast<size_t>(y) * w + x) * channels + c] =
                    static_cast<uint16_t>(std::lround(s * maxValue + ((x * 7 + y * 3 + c) % 5)));
            }
        }
    }
    return v;
}

OrthoEncodeOptions small() {
    OrthoEncodeOptions o;
    o.levels.tileSize = 16;
    return o;
}

TEST(OrthoEncoder, LosslessLevelsAreTheInputAndItsAverages) {
    test::TempDir dir;
    const int W = 64; // 16 << 2: pixel exact, levels 0..2
    const auto px = image(W, W, 3, 250);
    test::writeImage(dir.file("in.png"), W, W, 3, px, false);
    OrthoEncodeOptions o = small();
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
TEST(OrthoEncoder, UncompressedTiffInputGivesTheSameFilesAsPng) {
    for (const auto& [w, h] : {std::pair{64, 64}, std::pair{50, 30}}) {
        SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
        test::TempDir dir;
        const auto px = image(w, h, 3, 250);
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
        OrthoEncodeOptions o = small();
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
    OrthoEncodeOptions o = small();
    o.writeDxt = o.writeResiduals = false;
    encodeOrtho(dir.file("stripes.png"), dir.file("out"), o);
    const auto root = OrthoFileReader::open(dir.file("out/RGB.dat"))->readTile(0, 0, 0);
    EXPECT_EQ(root[5 + 5 * 20], 188);
}

TEST(OrthoEncoder, ColourResidualsRebuildBitForBit) {
    for (const TilePolicy compression : {TilePolicy::Deflate, TilePolicy::Jpeg}) {
        test::TempDir dir;
        const auto px = image(100, 80, 3, 240);
        test::writeImage(dir.file("in.png"), 100, 80, 3, px, false);
        OrthoEncodeOptions o = small();
        o.levels.tileSize = 8; // levels 0..4: both the in-memory levels and the subtrees
        o.writeTiff = o.writeDxt = false;
        o.residualCompression = compression;
        std::map<std::tuple<int, int, int>, std::vector<uint8_t>> recon;
        o.colourReconstruction = [&](int l, int tx, int ty, const std::vector<uint8_t>& r) { recon[{l, tx, ty}] = r; };
        const OrthoReport report = encodeOrtho(dir.file("in.png"), dir.file("out"), o);
        ASSERT_EQ(report.maxLevel, 4);
        ASSERT_EQ(static_cast<int64_t>(recon.size()), report.tiles);
        ColourProducer producer(std::make_shared<OrthoProducer>(dir.file("out/residuals/RGB.dat")));
        for (const auto& [key, tile] : recon) {
            const auto [l, tx, ty] = key;
            ASSERT_EQ(*producer.tile(l, tx, ty), tile) << "tile (" << l << "," << tx << "," << ty << ")";
        }
        for (const OrthoLevelReport& l : report.levels) {
            if (compression == TilePolicy::Deflate) {
                EXPECT_LE(l.residualMaxError, 1); // residuals are stored in steps of 2
            }
        }
    }
}

// A tile of one colour is encoded once per colour and its bytes are shared, but only under a
// parent whose rebuilt colours are that colour too (its residuals are then 128 everywhere).
// Under a parent of another colour, whether the parent is itself a shared tile or not, the tile
// is encoded as itself, and its stored residuals rebuild it from that parent.
TEST(OrthoEncoder, AOneColourTileIsSharedOnlyUnderAParentOfItsColour) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 32, 32, 3, std::vector<uint16_t>(32 * 32 * 3, 100), false);
    OrthoEncodeOptions o = small();
    o.levels.tileSize = 8;
    const OrthoLevels levels(dir.file("in.png"), o.levels);
    const OrthoTileEncoder encoder(levels, o);
    const int side = 8 + 4;
    const size_t bytes = static_cast<size_t>(side) * side * 3;
    const auto tileOf = [&](uint8_t colour, int tx, int ty) {
        TrueTile t;
        t.level = 2;
        t.tx = tx;
        t.ty = ty;
        t.pixels = Image8(side, side, 3);
        std::fill(t.pixels.pixels.begin(), t.pixels.pixels.end(), colour);
        return t;
    };
    // What a reader rebuilds from the tile's stored residuals and its parent.
    const auto rebuilt = [&](const EncodedOrthoTile& e, const std::vector<uint8_t>& parent, int tx, int ty) {
        const std::vector<uint8_t> residual = decodeOrthoTiff(*e.residual, side, 3, "residual tile");
        std::vector<uint8_t> out(bytes);
        upsampleColour(parent.data(), 8, 3, tx, ty, residual.data(), out.data());
        return out;
    };
    const std::vector<uint8_t> hundred(bytes, 100), ninetyEight(bytes, 98);
    const EncodedOrthoTile first = encoder.encode(tileOf(100, 0, 0), &hundred);
    const EncodedOrthoTile other = encoder.encode(tileOf(98, 1, 0), &ninetyEight);
    ASSERT_TRUE(first.uniform && other.uniform);
    EXPECT_EQ(*first.recon, hundred);

    // Under a shared tile of its colour: the first tile's bytes, shared.
    const EncodedOrthoTile shared = encoder.encode(tileOf(100, 1, 1), first.recon.get());
    EXPECT_EQ(shared.residual, first.residual);
    EXPECT_EQ(shared.tiff, first.tiff);
    EXPECT_EQ(rebuilt(shared, *first.recon, 1, 1), hundred);

    // Under a shared tile of 98, under a parent of 98 that is not shared, and under a parent of
    // many colours whose first pixel is 100: its own residuals, which rebuild it from that parent.
    std::vector<uint8_t> mixed(bytes);
    for (size_t k = 0; k < bytes; ++k) {
        mixed[k] = static_cast<uint8_t>(k < 3 ? 100 : 60 + (k * 37) % 90);
    }
    for (const std::vector<uint8_t>* parent :
         std::initializer_list<const std::vector<uint8_t>*>{other.recon.get(), &ninetyEight, &mixed}) {
        const EncodedOrthoTile own = encoder.encode(tileOf(100, 2, 3), parent);
        EXPECT_NE(*own.residual, *first.residual);
        EXPECT_EQ(rebuilt(own, *parent, 2, 3), *own.recon);
        if (parent != &mixed) {
            EXPECT_EQ(*own.recon, hundred);
        }
        EXPECT_EQ(*own.tiff, *first.tiff); // the same TIFF tile, which does not depend on the parent
    }
}

TEST(OrthoEncoder, IdenticalFilesForAnyThreadCount) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 90, 70, 4, image(90, 70, 4, 255), false);
    OrthoEncodeOptions o = small();
    o.levels.tileSize = 8;
    o.levels.threads = 1;
    encodeOrtho(dir.file("in.png"), dir.file("one"), o);
    o.levels.threads = 2;
    encodeOrtho(dir.file("in.png"), dir.file("two"), o);
    for (const char* f : {"/RGB.dat", "/dxt/RGB.dat", "/residuals/RGB.dat"}) {
        const std::string a = test::readFile(dir.file("one") + f);
        EXPECT_GT(a.size(), 500u) << f;
        EXPECT_EQ(a, test::readFile(dir.file("two") + f)) << f;
    }
    // Without colour residuals the input is walked in one pass, its subtrees taken by whichever
    // thread is free: the files do not follow the thread count.
    o.writeResiduals = false;
    for (const int threads : {1, 2, 3}) {
        o.levels.threads = threads;
        encodeOrtho(dir.file("in.png"), dir.file("single" + std::to_string(threads)), o);
    }
    for (const char* f : {"/RGB.dat", "/dxt/RGB.dat"}) {
        const std::string a = test::readFile(dir.file("single1") + f);
        EXPECT_EQ(a, test::readFile(dir.file("single2") + f)) << f;
        EXPECT_EQ(a, test::readFile(dir.file("single3") + f)) << f;
    }
}

// The default outputs take two walks (TIFF and DXT tiles first, then the subtrees' residuals):
// each file is the one its output alone gives (the residual tiles, in another order), and so
// are each level's statistics; every tile's rebuilt colours are those a reader rebuilds.
TEST(OrthoEncoder, AllThreeOutputsAreEachOutputsOwnRun) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 100, 80, 3, image(100, 80, 3, 250), false);
    OrthoEncodeOptions o = small();
    o.levels.tileSize = 8; // M = 4: levels 0..2 whole, and subtrees of levels 3..4 (0 and 1..4 alone)
    o.levels.threads = 2;
    std::map<std::tuple<int, int, int>, std::vector<uint8_t>> recon;
    int64_t calls = 0;
    o.colourReconstruction = [&](int l, int tx, int ty, const std::vector<uint8_t>& r) {
        ++calls;
        recon[{l, tx, ty}] = r;
    };
    std::vector<std::pair<int64_t, int64_t>> progress;
    o.progress = [&](int64_t done, int64_t total) { progress.emplace_back(done, total); };
    const OrthoReport all = encodeOrtho(dir.file("in.png"), dir.file("all"), o);
    ASSERT_EQ(all.maxLevel, 4);
    EXPECT_EQ(calls, all.tiles);
    EXPECT_EQ(static_cast<int64_t>(recon.size()), all.tiles);
    ColourProducer producer(std::make_shared<OrthoProducer>(dir.file("all/residuals/RGB.dat")));
    for (const auto& [key, tile] : recon) {
        const auto [l, tx, ty] = key;
        ASSERT_EQ(*producer.tile(l, tx, ty), tile) << "tile (" << l << "," << tx << "," << ty << ")";
    }
    ASSERT_FALSE(progress.empty());
    for (size_t i = 1; i < progress.size(); ++i) {
        ASSERT_EQ(progress[i].first, progress[i - 1].first + 1);
        ASSERT_EQ(progress[i].second, progress[0].second);
    }
    EXPECT_EQ(progress.back().first, progress.back().second);

    o.colourReconstruction = nullptr;
    o.progress = nullptr;
    OrthoEncodeOptions pictures = o;
    pictures.writeResiduals = false;
    const OrthoReport p = encodeOrtho(dir.file("in.png"), dir.file("pictures"), pictures);
    for (const char* f : {"/RGB.dat", "/dxt/RGB.dat"}) {
        const std::string a = test::readFile(dir.file("all") + f);
        EXPECT_GT(a.size(), 500u) << f;
        EXPECT_EQ(a, test::readFile(dir.file("pictures") + f)) << f;
    }
    OrthoEncodeOptions residuals = o;
    residuals.writeTiff = residuals.writeDxt = false;
    const OrthoReport r = encodeOrtho(dir.file("in.png"), dir.file("residuals"), residuals);
    const auto mine = OrthoFileReader::open(dir.file("all/residuals/RGB.dat"));
    const auto alone = OrthoFileReader::open(dir.file("residuals/residuals/RGB.dat"));
    for (int l = 0; l <= 4; ++l) {
        for (int ty = 0; ty < (1 << l); ++ty) {
            for (int tx = 0; tx < (1 << l); ++tx) {
                ASSERT_EQ(mine->readTile(l, tx, ty), alone->readTile(l, tx, ty)) << l << "," << tx << "," << ty;
            }
        }
    }
    EXPECT_EQ(all.bytes.at(2), r.bytes.at(0)); // the same tiles, shared alike
    ASSERT_EQ(all.levels.size(), 5u);
    for (size_t l = 0; l < all.levels.size(); ++l) {
        const OrthoLevelReport& a = all.levels[l];
        EXPECT_EQ(a.tiles, int64_t{1} << (2 * l));
        EXPECT_EQ(a.tiles, r.levels[l].tiles);
        EXPECT_EQ(a.dxtPsnr, p.levels[l].dxtPsnr) << l;
        EXPECT_EQ(a.residualMaxError, r.levels[l].residualMaxError) << l;
        EXPECT_EQ(a.residualRmsError, r.levels[l].residualRmsError) << l;
        EXPECT_EQ(a.clampedResiduals, r.levels[l].clampedResiduals) << l;
    }
}

TEST(OrthoEncoder, DxtWithinItsErrorAndNoBorderFiles) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 64, 64, 3, image(64, 64, 3, 230), false);
    OrthoEncodeOptions o = small();
    o.border = 0;
    o.writeResiduals = false;
    const OrthoReport report = encodeOrtho(dir.file("in.png"), dir.file("out"), o);
    for (const OrthoLevelReport& l : report.levels) {
        EXPECT_GT(l.dxtPsnr, 22.0) << "level " << l.level; // three independent channels: hard for DXT1
    }
    const auto dxt = OrthoFileReader::open(dir.file("out/dxt/RGB.dat"));
    EXPECT_EQ(dxt->header().flags, OrthoHeader::kFlagDxt | OrthoHeader::kFlagNoBorder);
    EXPECT_EQ(dxt->header().channels, 3);
    const auto tiff = OrthoFileReader::open(dir.file("out/RGB.dat"));
    EXPECT_EQ(tiff->header().flags, OrthoHeader::kFlagNoBorder);
    EXPECT_EQ(tiff->header().tilePixels(), 16);
    // DXT1 keeps each 4x4 block within a colour line: on this smooth image, close to the source.
    const auto a = tiff->readTile(2, 1, 1);
    const auto b = dxt->readTile(2, 1, 1);
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k) {
        ASSERT_LE(std::abs(a[k] - b[k]), 24) << k;
    }
    const OrthoVerifyReport v = verifyOrtho(dir.file("out/dxt/RGB.dat"), dir.file("in.png"), {});
    EXPECT_TRUE(v.ok);
    EXPECT_EQ(v.mode, "dxt");
    // The PSNR the encoder states is what a reader gets.
    ASSERT_EQ(v.levels.size(), report.levels.size());
    for (size_t l = 0; l < v.levels.size(); ++l) {
        EXPECT_NEAR(v.levels[l].psnr, report.levels[l].dxtPsnr, 1e-9);
    }
}

TEST(OrthoEncoder, SixteenBitInputRoundsToEightBits) {
    test::TempDir dir;
    const auto px = image(32, 32, 1, 65000);
    test::writeImage(dir.file("in16.tif"), 32, 32, 1, px, true);
    OrthoEncodeOptions o = small();
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
                test::writeImage(dir.file("in.png"), w, h, channels, image(w, h, channels, full - 8), sixteen);
                // The samples as stored (the PNG writer may have un-premultiplied an alpha channel).
                std::vector<uint16_t> px(static_cast<size_t>(w) * h * channels);
                RasterSource::open(dir.file("in.png"))->readUInt16(0, 0, w, h, 0, channels, px.data());
                OrthoEncodeOptions o = small();
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

// The Deflate level trades time for bytes only: every tile decodes to the same pixels.
TEST(OrthoEncoder, DeflateLevelsDecodeToTheSameTiles) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 100, 60, 3, image(100, 60, 3, 255), false);
    OrthoEncodeOptions o = small();
    o.writeDxt = o.writeResiduals = false;
    std::vector<uint64_t> bytes;
    for (const int level : {1, 6, 12}) {
        o.deflateLevel = level;
        bytes.push_back(encodeOrtho(dir.file("in.png"), dir.file("l" + std::to_string(level)), o).bytes.at(0));
    }
    EXPECT_GT(bytes[0], bytes[1]);
    EXPECT_GT(bytes[1], bytes[2]);
    const auto fastest = OrthoFileReader::open(dir.file("l1/RGB.dat"));
    const auto smallest = OrthoFileReader::open(dir.file("l12/RGB.dat"));
    ASSERT_EQ(fastest->header().maxLevel, 3);
    for (int l = 0; l <= 3; ++l) {
        for (int ty = 0; ty < (1 << l); ++ty) {
            for (int tx = 0; tx < (1 << l); ++tx) {
                ASSERT_EQ(fastest->readTile(l, tx, ty), smallest->readTile(l, tx, ty)) << l << "," << tx << "," << ty;
            }
        }
    }
    o.deflateLevel = 13;
    EXPECT_THROW(encodeOrtho(dir.file("in.png"), dir.file("l13"), o), Error);
    EXPECT_FALSE(std::filesystem::exists(dir.file("l13")));
}

// So does the residual Deflate level: the residual tiles decode to the same residuals, and
// the reports' errors (closed loop over them) are the same.
TEST(OrthoEncoder, ResidualDeflateLevelsDecodeToTheSameResiduals) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 100, 60, 3, image(100, 60, 3, 255), false);
    OrthoEncodeOptions o = small();
    o.writeDxt = o.writeTiff = false;
    std::vector<OrthoReport> reports;
    for (const int level : {1, 2, 12}) {
        o.residualDeflateLevel = level;
        reports.push_back(encodeOrtho(dir.file("in.png"), dir.file("r" + std::to_string(level)), o));
    }
    EXPECT_GT(reports[0].bytes.at(0), reports[2].bytes.at(0));
    EXPECT_GE(reports[1].bytes.at(0), reports[2].bytes.at(0));
    const auto fastest = OrthoFileReader::open(dir.file("r1/residuals/RGB.dat"));
    const auto smallest = OrthoFileReader::open(dir.file("r12/residuals/RGB.dat"));
    for (int l = 0; l <= fastest->header().maxLevel; ++l) {
        for (int ty = 0; ty < (1 << l); ++ty) {
            for (int tx = 0; tx < (1 << l); ++tx) {
                ASSERT_EQ(fastest->readTile(l, tx, ty), smallest->readTile(l, tx, ty)) << l << "," << tx << "," << ty;
            }
        }
        EXPECT_EQ(reports[0].levels[static_cast<size_t>(l)].residualRmsError,
                  reports[2].levels[static_cast<size_t>(l)].residualRmsError);
    }
    for (const int level : {-1, 13}) {
        o.residualDeflateLevel = level;
        EXPECT_THROW(encodeOrtho(dir.file("in.png"), dir.file("bad"), o), Error);
        EXPECT_FALSE(std::filesystem::exists(dir.file("bad")));
    }
}

// The default residual Deflate level (0) is chosen per tile: level 2 where the stored residuals
// are smooth (mean distance from 128 below 1/2) and for the root's colours, level 1 where they
// are grainy. Each tile is the very blob that level would give.
TEST(OrthoEncoder, DefaultResidualDeflateLevelIsChosenPerTileFromItsResiduals) {
    test::TempDir dir;
    const int W = 64;
    // West half a gentle gradient (residuals 128), east half grain: both kinds of tile.
    std::vector<uint16_t> px(static_cast<size_t>(W) * W * 3);
    uint32_t state = 12345;
    for (int y = 0; y < W; ++y) {
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 3; ++c) {
                state = state * 1664525u + 1013904223u;
                px[(static_cast<size_t>(y) * W + x) * 3 + c] =
                    static_cast<uint16_t>(x < W / 2 ? 60 + x + 2 * c : 40 + (state >> 24) % 160);
            }
        }
    }
    test::writeImage(dir.file("in.png"), W, W, 3, px, false);
    OrthoEncodeOptions o = small();
    o.writeDxt = o.writeTiff = false;
    for (const int level : {0, 1, 2}) {
        o.residualDeflateLevel = level;
        encodeOrtho(dir.file("in.png"), dir.file("r" + std::to_string(level)), o);
    }
    const auto chosen = OrthoFileReader::open(dir.file("r0/residuals/RGB.dat"));
    const auto one = OrthoFileReader::open(dir.file("r1/residuals/RGB.dat"));
    const auto two = OrthoFileReader::open(dir.file("r2/residuals/RGB.dat"));
    int smooth = 0, grainy = 0;
    for (int l = 0; l <= chosen->header().maxLevel; ++l) {
        for (int ty = 0; ty < (1 << l); ++ty) {
            for (int tx = 0; tx < (1 << l); ++tx) {
                const std::vector<uint8_t> stored = chosen->readTile(l, tx, ty);
                uint64_t distance = 0;
                for (const uint8_t v : stored) {
                    distance += static_cast<uint64_t>(std::abs(static_cast<int>(v) - 128));
                }
                const bool levelTwo = l == 0 || 2 * distance < stored.size();
                const auto blob1 = one->readTileBytes(l, tx, ty);
                const auto blob2 = two->readTileBytes(l, tx, ty);
                EXPECT_EQ(chosen->readTileBytes(l, tx, ty), levelTwo ? blob2 : blob1) << l << "," << tx << "," << ty;
                if (l > 0 && blob1 != blob2) {
                    ++(levelTwo ? smooth : grainy);
                }
            }
        }
    }
    EXPECT_GT(smooth, 0);
    EXPECT_GT(grainy, 0);
}

TEST(OrthoEncoder, BadInputWritesNothing) {
    test::TempDir dir;
    std::vector<float> f(16 * 16, 0.5f);
    test::writeFloatRaster(dir.file("float.tif"), 16, 16, f);
    EXPECT_THROW(encodeOrtho(dir.file("float.tif"), dir.file("out"), small()), Error);
    EXPECT_THROW(encodeOrtho(dir.file("missing.png"), dir.file("out"), small()), Error);
    test::writeImage(dir.file("rgba.png"), 32, 32, 4, image(32, 32, 4, 255), false);
    OrthoEncodeOptions o = small();
    o.compression = TilePolicy::Jpeg;
    EXPECT_THROW(encodeOrtho(dir.file("rgba.png"), dir.file("out"), o), Error);
    o = small();
    o.border = 3;
    EXPECT_THROW(encodeOrtho(dir.file("rgba.png"), dir.file("out"), o), Error);
    EXPECT_FALSE(std::filesystem::exists(dir.file("out")));
}

TEST(OrthoEncoder, AFailureMidRunLeavesThePreviousOutputs) {
    test::TempDir dir;
    // A PNG cut short: its header opens, its pixels fail to decode once the levels are read,
    // after the three writers have started.
    test::writeImage(dir.file("in.png"), 256, 256, 3, image(256, 256, 3, 255), false);
    const std::string whole = test::readFile(dir.file("in.png"));
    {
        std::ofstream cut(dir.file("cut.png"), std::ios::binary);
        cut.write(whole.data(), static_cast<std::streamsize>(whole.size() / 2));
    }
    const std::string out = dir.file("out");
    encodeOrtho(dir.file("in.png"), out, small());
    const std::string before = test::readFile(out + "/RGB.dat");
    const std::string beforeDxt = test::readFile(out + "/dxt/RGB.dat");
    EXPECT_THROW(encodeOrtho(dir.file("cut.png"), out, small()), Error);
    EXPECT_EQ(test::readFile(out + "/RGB.dat"), before);
    EXPECT_EQ(test::readFile(out + "/dxt/RGB.dat"), beforeDxt);
    size_t entries = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(out)) {
        entries += e.is_regular_file();
    }
    EXPECT_EQ(entries, 3u); // the previous three files, no temporaries or staging left
    // Into a new directory: nothing at all.
    EXPECT_THROW(encodeOrtho(dir.file("cut.png"), dir.file("fresh/out"), small()), Error);
    EXPECT_FALSE(std::filesystem::exists(dir.file("fresh")));
    // With more threads than cores, and in both walk orders (residuals alone: levels first): the
    // subtree that meets the damage stops the others, which do not wait for it, and the error
    // names the file.
    for (const int threads : {1, 3}) {
        for (const bool residualsOnly : {false, true}) {
            OrthoEncodeOptions o = small();
            o.levels.threads = threads;
            if (residualsOnly) {
                o.writeTiff = o.writeDxt = false;
            }
            const std::string where = dir.file("t" + std::to_string(threads) + (residualsOnly ? "r" : "a"));
            try {
                encodeOrtho(dir.file("cut.png"), where, o);
                ADD_FAILURE() << "no error with " << threads << " threads";
            } catch (const Error& e) {
                const std::string message = e.what();
                EXPECT_EQ(message.rfind(dir.file("cut.png") + ": cannot read: damaged or truncated PNG", 0), 0u)
                    << message;
            }
            EXPECT_FALSE(std::filesystem::exists(where));
        }
    }
}

} // namespace
} // namespace pyramid
