// preprocessOrtho as a library, its outputs: the same files for any thread count, each of the three
// outputs the one its own run gives, DXT within its error and files without borders, the Deflate
// level trading time for bytes only, and a failure (bad input, or mid-run) that writes nothing
// and leaves the previous outputs.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/runtime/colour_producer.hpp"
#include "libpyramid/verify/ortho_verify.hpp"
#include "tests/support/ortho_images.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::orthoImage;
using test::smallOrtho;

TEST(OrthoEncoder, IdenticalFilesForAnyThreadCount) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 90, 70, 4, orthoImage(90, 70, 4, 255), false);
    OrthoEncodeOptions o = smallOrtho();
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

// Computed colours whose reads are counted (pixels read, every channel range alike).
class CountedPixels final : public BytePixels {
public:
    void readBytes(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out) const override {
        read += int64_t{x1 - x0} * (y1 - y0);
        for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
                for (int c = c0; c < c1; ++c) {
                    *out++ = static_cast<uint8_t>((x * 7 + y * 13 + c * 85 + (x * y) % 23) & 0xff);
                }
            }
        }
    }
    mutable std::atomic<int64_t> read{0};
};

// A build in two walks keeps the first walk's subtrees for the second when they fit in
// keptSubtreeBytes: the input is then read once instead of twice, and the files are the same
// bytes as those of the build that reads it again (0, or a budget they do not fit), whatever
// the thread count; so are the rebuilt colours handed out and the progress.
TEST(OrthoEncoder, TheSecondWalkEncodesTheFirstWalksSubtreesWhenTheyFit) {
    test::TempDir dir;
    RasterInfo info;
    info.width = 100;
    info.height = 70;
    info.channels = 3;
    info.type = SampleType::UInt8;
    const auto pixels = std::make_shared<CountedPixels>();
    const auto source = RasterSource::fromPixels("counted", info, pixels);
    OrthoEncodeOptions o = smallOrtho();
    o.levels.tileSize = 8; // M = 4, subtrees of levels 3 and 4: 64 of 5 tiles (12^2 x 3 bytes each)
    const int64_t needed = 64 * 5 * 12 * 12 * 3;
    struct Run {
        std::string name;
        int64_t budget;
        int threads;
    };
    std::map<std::string, int64_t> reads;
    std::map<std::string, std::vector<std::tuple<int, int, int, std::vector<uint8_t>>>> recon;
    std::map<std::string, int64_t> steps;
    for (const Run& run : {Run{"kept1", needed, 1}, Run{"kept3", int64_t{64} << 20, 3}, Run{"again1", 0, 1},
                           Run{"again2", needed - 1, 2}}) {
        o.keptSubtreeBytes = run.budget;
        o.levels.threads = run.threads;
        o.colourReconstruction = [&](int l, int tx, int ty, const std::vector<uint8_t>& r) {
            recon[run.name].emplace_back(l, tx, ty, r);
        };
        o.progress = [&](int64_t done, int64_t) { steps[run.name] = done; };
        pixels->read = 0;
        const OrthoReport report = encodeOrtho(*source, dir.file(run.name), o);
        ASSERT_EQ(report.maxLevel, 4);
        reads[run.name] = pixels->read;
    }
    // The finest level is 128^2, sampled from the input's 100 x 70 (with the footprints' borders).
    EXPECT_GT(reads["kept1"], 100 * 70);
    EXPECT_EQ(reads["kept3"], reads["kept1"]);
    EXPECT_EQ(reads["again1"], 2 * reads["kept1"]);
    EXPECT_EQ(reads["again2"], reads["again1"]);
    for (const char* f : {"/RGB.dat", "/dxt/RGB.dat", "/residuals/RGB.dat"}) {
        const std::string a = test::readFile(dir.file("kept1") + f);
        EXPECT_GT(a.size(), 500u) << f;
        for (const char* other : {"kept3", "again1", "again2"}) {
            EXPECT_EQ(a, test::readFile(dir.file(other) + f)) << other << f;
        }
    }
    EXPECT_EQ(recon["kept1"], recon["again1"]);
    EXPECT_EQ(steps["kept1"], steps["again1"]);
    EXPECT_EQ(steps["kept3"], steps["again2"]);
}

// An image decoded whole (a PNG, its rows in blocks of 2 MB: here rows 0..776 and 777..799)
// gives back the rows the last walk reading it has passed, the first block halfway through (a
// read of it after that would fail the build): the files are those of the build that reads it
// twice (no subtrees kept) and keeps every row. A caller's own source keeps its rows.
TEST(OrthoEncoder, TheLastWalkLetsADecodedImageGiveBackTheRowsItPassed) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 900, 800, 3, orthoImage(900, 800, 3, 255), false);
    OrthoEncodeOptions o = smallOrtho();
    o.levels.tileSize = 32; // every core: the subtrees sampled out of order
    encodeOrtho(dir.file("in.png"), dir.file("kept"), o);
    const auto source = RasterSource::open(dir.file("in.png"));
    encodeOrtho(*source, dir.file("caller"), o);
    std::vector<uint16_t> sample(3);
    source->readUInt16(0, 0, 1, 1, 0, 3, sample.data()); // still there
    o.keptSubtreeBytes = 0; // the second walk samples the input again: no row is given back
    encodeOrtho(dir.file("in.png"), dir.file("again"), o);
    for (const char* f : {"/RGB.dat", "/dxt/RGB.dat", "/residuals/RGB.dat"}) {
        const std::string a = test::readFile(dir.file("kept") + f);
        EXPECT_GT(a.size(), 500u) << f;
        EXPECT_EQ(a, test::readFile(dir.file("caller") + f)) << f;
        EXPECT_EQ(a, test::readFile(dir.file("again") + f)) << f;
    }
}

// The default outputs take two walks (TIFF and DXT tiles first, then the subtrees' residuals):
// each file is the one its output alone gives (the residual tiles, in another order), and so
// are each level's statistics; every tile's rebuilt colours are those a reader rebuilds.
TEST(OrthoEncoder, AllThreeOutputsAreEachOutputsOwnRun) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 100, 80, 3, orthoImage(100, 80, 3, 250), false);
    OrthoEncodeOptions o = smallOrtho();
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
    test::writeImage(dir.file("in.png"), 64, 64, 3, orthoImage(64, 64, 3, 230), false);
    OrthoEncodeOptions o = smallOrtho();
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

// The Deflate level trades time for bytes only: every tile decodes to the same pixels.
TEST(OrthoEncoder, DeflateLevelsDecodeToTheSameTiles) {
    test::TempDir dir;
    test::writeImage(dir.file("in.png"), 100, 60, 3, orthoImage(100, 60, 3, 255), false);
    OrthoEncodeOptions o = smallOrtho();
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

TEST(OrthoEncoder, BadInputWritesNothing) {
    test::TempDir dir;
    std::vector<float> f(16 * 16, 0.5f);
    test::writeFloatRaster(dir.file("float.tif"), 16, 16, f);
    EXPECT_THROW(encodeOrtho(dir.file("float.tif"), dir.file("out"), smallOrtho()), Error);
    EXPECT_THROW(encodeOrtho(dir.file("missing.png"), dir.file("out"), smallOrtho()), Error);
    test::writeImage(dir.file("rgba.png"), 32, 32, 4, orthoImage(32, 32, 4, 255), false);
    OrthoEncodeOptions o = smallOrtho();
    o.compression = TilePolicy::Jpeg;
    EXPECT_THROW(encodeOrtho(dir.file("rgba.png"), dir.file("out"), o), Error);
    o = smallOrtho();
    o.border = 3;
    EXPECT_THROW(encodeOrtho(dir.file("rgba.png"), dir.file("out"), o), Error);
    EXPECT_FALSE(std::filesystem::exists(dir.file("out")));
}

TEST(OrthoEncoder, AFailureMidRunLeavesThePreviousOutputs) {
    test::TempDir dir;
    // A PNG cut short: its header opens, its pixels fail to decode once the levels are read,
    // after the three writers have started.
    test::writeImage(dir.file("in.png"), 256, 256, 3, orthoImage(256, 256, 3, 255), false);
    const std::string whole = test::readFile(dir.file("in.png"));
    {
        std::ofstream cut(dir.file("cut.png"), std::ios::binary);
        cut.write(whole.data(), static_cast<std::streamsize>(whole.size() / 2));
    }
    const std::string out = dir.file("out");
    encodeOrtho(dir.file("in.png"), out, smallOrtho());
    const std::string before = test::readFile(out + "/RGB.dat");
    const std::string beforeDxt = test::readFile(out + "/dxt/RGB.dat");
    EXPECT_THROW(encodeOrtho(dir.file("cut.png"), out, smallOrtho()), Error);
    EXPECT_EQ(test::readFile(out + "/RGB.dat"), before);
    EXPECT_EQ(test::readFile(out + "/dxt/RGB.dat"), beforeDxt);
    size_t entries = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(out)) {
        entries += e.is_regular_file();
    }
    EXPECT_EQ(entries, 3u); // the previous three files, no temporaries or staging left
    // Into a new directory: nothing at all.
    EXPECT_THROW(encodeOrtho(dir.file("cut.png"), dir.file("fresh/out"), smallOrtho()), Error);
    EXPECT_FALSE(std::filesystem::exists(dir.file("fresh")));
    // With more threads than cores, and in both walk orders (residuals alone: levels first): the
    // subtree that meets the damage stops the others, which do not wait for it, and the error
    // names the file.
    for (const int threads : {1, 3}) {
        for (const bool residualsOnly : {false, true}) {
            OrthoEncodeOptions o = smallOrtho();
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
