// Planar imagery of several resolutions (ortho_levels.hpp, "Several resolutions"; doc/input.md,
// "Several resolutions"): a coarse base image and a fine inset, one run of preprocessOrtho. The
// pyramid goes down to the inset's level over the inset and stops at the base's level elsewhere
// (the base read at its own level, not resampled onto the inset's grid): its colours are the
// inset's in the inset and the base's elsewhere, `pyramid verify` passes, the files are a small
// fraction of the same mosaic encoded as one resolution, and threads and --part give the same bytes.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/verify/ortho_verify.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/preview_pngs.hpp"

namespace pyramid {
namespace {

// UTM 10N metres from the mosaic's north-west corner. The base: 96 x 96 pixels of 20 m. The
// inset: 240 x 240 pixels of 1 m, 840 m in from the corner. With 32-pixel tiles the grid of
// 1920 1 m pixels has 6 levels; the base needs levels 0..2 (96 pixels, more than 64).
constexpr double kWest = 500000.0, kNorth = 5200000.0;
constexpr int kBase = 96, kInset = 240, kTile = 32, kBaseLevel = 2, kInsetLevel = 6;
constexpr double kBaseStep = 20.0, kInsetAt = 840.0;

int byte(double v) { return static_cast<int>(std::lround(std::fmin(255.0, std::fmax(0.0, v)))); }
std::array<int, 3> baseColour(double e, double s) {
    return {byte(110.0 + 60.0 * std::sin(e / 500.0)), byte(120.0 + 50.0 * std::cos(s / 400.0)), 70};
}
std::array<int, 3> insetColour(double e, double s) {
    return {byte(210.0 + 30.0 * std::sin(e / 30.0)), 30, byte(170.0 + 60.0 * std::cos(s / 25.0))};
}

struct Maps {
    std::string directory, base, inset;
};

template <class Colour>
void writeRgb(const std::string& path, int n, double west, double north, double step, const Colour& colour) {
    std::vector<uint8_t> rgb(static_cast<size_t>(n) * n * 3);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const auto c = colour((i + 0.5) * step, (j + 0.5) * step);
            for (size_t k = 0; k < 3; ++k) {
                rgb[(static_cast<size_t>(j) * n + i) * 3 + k] = static_cast<uint8_t>(c[k]);
            }
        }
    }
    test::writeGeoTiffRgb(path, n, n, rgb, test::projectedTags(32610, west, north, step));
}

Maps writeMaps(const test::TempDir& dir) {
    Maps m{dir.file("maps"), dir.file("maps/base.tif"), dir.file("maps/inset.tif")};
    std::filesystem::create_directories(m.directory);
    writeRgb(m.base, kBase, kWest, kNorth, kBaseStep, baseColour);
    writeRgb(m.inset, kInset, kWest + kInsetAt, kNorth - kInsetAt, 1.0, insetColour);
    return m;
}

OrthoEncodeOptions options() {
    OrthoEncodeOptions o;
    o.levels.tileSize = kTile;
    o.levels.threads = 2;
    return o;
}

// The deepest stored tile holding the point (e, s) metres east and south of the corner: its
// level and the colour of the pixel there.
std::pair<int, std::array<int, 3>> deepestAt(const std::string& file, double e, double s) {
    const auto set = openOrthoSet(file);
    std::pair<int, std::array<int, 3>> d{-1, {}};
    const double u = e / 1920.0, v = 1.0 - s / 1920.0; // y up
    for (int l = 0; l <= set->maxLevel(); ++l) {
        const double x = u * (kTile << l), y = v * (kTile << l);
        const int tx = static_cast<int>(x) / kTile, ty = static_cast<int>(y) / kTile;
        if (!set->hasTile(l, tx, ty)) {
            break;
        }
        const std::vector<uint8_t> tile = set->tile(l, tx, ty);
        const int side = kTile + 4, px = static_cast<int>(x) - tx * kTile + 2, py = static_cast<int>(y) - ty * kTile + 2;
        d.first = l;
        for (size_t k = 0; k < 3; ++k) {
            d.second[k] = tile[(static_cast<size_t>(py) * side + px) * 3 + k];
        }
    }
    return d;
}

class PlanarOrthoMultires : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir();
        maps_ = new Maps(writeMaps(*dir_));
        encodeOrtho(std::vector<std::string>{maps_->base, maps_->inset}, dir_->file("out"), options());
    }
    static void TearDownTestSuite() {
        delete maps_;
        delete dir_;
    }
    static test::TempDir* dir_;
    static Maps* maps_;
};
test::TempDir* PlanarOrthoMultires::dir_ = nullptr;
Maps* PlanarOrthoMultires::maps_ = nullptr;

TEST_F(PlanarOrthoMultires, TheInsetsLevelWhereItIsTheBasesElsewhere) {
    for (const std::string sub : {"", "dxt/"}) {
        const std::string file = dir_->file("out/" + sub + "RGB.dat");
        for (const auto& [e, s] : {std::pair{960.0, 960.0}, std::pair{900.0, 1050.0}, std::pair{1060.0, 870.0}}) {
            const auto [level, colour] = deepestAt(file, e, s);
            EXPECT_EQ(level, kInsetLevel) << sub << e << "," << s;
            const auto want = insetColour(e - kInsetAt, s - kInsetAt);
            for (size_t k = 0; k < 3; ++k) {
                EXPECT_NEAR(colour[k], want[k], sub.empty() ? 3 : 24) << sub << e << "," << s << " channel " << k;
            }
        }
        for (const auto& [e, s] : {std::pair{100.0, 100.0}, std::pair{1800.0, 300.0}, std::pair{300.0, 1700.0},
                                   std::pair{1700.0, 1800.0}}) {
            const auto [level, colour] = deepestAt(file, e, s);
            EXPECT_EQ(level, kBaseLevel) << sub << e << "," << s;
            const auto want = baseColour(e, s);
            for (size_t k = 0; k < 3; ++k) {
                EXPECT_NEAR(colour[k], want[k], sub.empty() ? 4 : 24) << sub << e << "," << s << " channel " << k;
            }
        }
    }
}

TEST_F(PlanarOrthoMultires, VerifiesAndIsSmall) {
    OrthoVerifyOptions v;
    v.threads = 2;
    const OrthoVerifyReport tiles = verifyOrtho(dir_->file("out/RGB.dat"), maps_->directory, v);
    EXPECT_TRUE(tiles.ok);
    for (const OrthoVerifyLevel& l : tiles.levels) {
        EXPECT_EQ(l.maxError, 0) << "level " << l.level;
    }
    v.colourResiduals = true;
    EXPECT_TRUE(verifyOrtho(dir_->file("out/residuals/RGB.dat"), maps_->directory, v).ok);
    // One resolution: 4^6 finest tiles of the 1 m grid in each output; here the inset's few
    // dozen and the base's levels.
    EXPECT_LT(test::bytesUnder(dir_->file("out")), uint64_t{1} << 20);
}

TEST_F(PlanarOrthoMultires, TheSameBytesWhateverTheThreads) {
    OrthoEncodeOptions one = options();
    one.levels.threads = 1;
    encodeOrtho(std::vector<std::string>{maps_->base, maps_->inset}, dir_->file("one"), one);
    EXPECT_TRUE(test::filesUnder(dir_->file("out")) == test::filesUnder(dir_->file("one")));
}

// The tiles left out (TIFF and DXT tiles beyond the base's resolution, doc/format.md 1.5) are
// what the format allows: `pyramid check` counts them and passes, and `pyramid preview` draws
// them as a reader does, magnified from their parents: the base's colours beyond the inset.
TEST_F(PlanarOrthoMultires, CheckAndPreviewTakeTheTilesLeftOut) {
    const test::RunResult c = test::run(test::programPath("pyramid") + " check -q --json '" + dir_->file("out") + "'");
    ASSERT_EQ(c.exitCode, 0) << c.out << c.err;
    const nlohmann::json report = nlohmann::json::parse(c.out);
    EXPECT_TRUE(report["ok"].get<bool>());
    EXPECT_GT(report["tiles_left_out"].get<int64_t>(), 0) << c.out;
    // 256 pixels over the 1920 m: level 3, below the base's level 2 outside the inset.
    for (const auto& [file, tolerance] : std::map<std::string, int>{{"out/RGB.dat", 6}, {"out/dxt/RGB.dat", 24}}) {
        const std::string png = dir_->file(file + ".png");
        const test::RunResult r =
            test::run(test::programPath("pyramid") + " preview '" + dir_->file(file) + "' --size 256 -o '" + png + "'");
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const test::Png p = test::readPng(png);
        ASSERT_EQ(p.width, 256);
        for (const int at : {20, 60, 230}) { // preview pixels (at, at) from the north-west corner
            const double metres = (at + 0.5) * 1920.0 / 256.0;
            const std::array<int, 3> want = baseColour(metres, metres);
            for (size_t k = 0; k < 3; ++k) {
                const int sample = p.samples[(static_cast<size_t>(at) * static_cast<size_t>(p.width) +
                                              static_cast<size_t>(at)) * static_cast<size_t>(p.channels) + k];
                const int got = p.depth == 8 ? sample / 257 : sample; // samples read as 16 bits
                EXPECT_NEAR(got, want[k], tolerance) << file << " pixel " << at << " channel " << k;
            }
        }
    }
}

// A build split into parts (--part I/N, then pyramid merge) writes the single run's sets, byte
// for byte, in each walk order (two walks; top levels first; subtrees first): the parts carry
// that the TIFF and DXT tiles beyond the base's resolution are left out.
TEST_F(PlanarOrthoMultires, PartsMergeIntoTheSingleRunsSets) {
    for (const std::string outputs : {"tiff,dxt,residuals", "residuals", "dxt"}) {
        const std::string cmd = test::programPath("preprocessOrtho") + " " + maps_->base + " " + maps_->inset +
                                " --outputs " + outputs + " --tile-size 32 -q -o ";
        const std::string one = dir_->file("one-" + outputs);
        ASSERT_EQ(test::run(cmd + one).exitCode, 0);
        const std::string parts = dir_->file("parts-" + outputs);
        for (int i = 0; i < 3; ++i) {
            const test::RunResult r = test::run(cmd + parts + " --threads " + std::to_string(1 + i % 2) + " --part " +
                                                std::to_string(i) + "/3");
            ASSERT_EQ(r.exitCode, 0) << r.err;
        }
        const test::RunResult m = test::run(test::programPath("pyramid") + " merge -q " + parts + "/RGB.part-*");
        ASSERT_EQ(m.exitCode, 0) << m.err;
        auto merged = test::filesUnder(parts);
        std::erase_if(merged, [](const auto& f) { return f.first.find(".part-") != std::string::npos; });
        EXPECT_TRUE(merged == test::filesUnder(one)) << outputs;
    }
}

TEST_F(PlanarOrthoMultires, ARegionOrDenseBuildIsRefusedWithTheReason) {
    OrthoEncodeOptions o = options();
    o.layout = PyramidLayout::Dense;
    try {
        encodeOrtho(std::vector<std::string>{maps_->base, maps_->inset}, dir_->file("dense"), o);
        FAIL() << "a dense layout of several resolutions was accepted";
    } catch (const OptionError& e) {
        EXPECT_NE(std::string(e.what()).find("several resolutions"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir_->file("dense/RGB.dat")));
}

} // namespace
} // namespace pyramid
