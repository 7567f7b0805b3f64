// preprocessDem's options as a user gives them: --max-error, --scale auto, --max-level,
// --band, --nodata, the tile-size warning, 8-bit input, and the errors of impossible values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::programPath;
using test::run;

std::string shellQuoted(const std::string& s) { return "'" + s + "'"; }

size_t lines(const std::string& s) { return static_cast<size_t>(std::count(s.begin(), s.end(), '\n')); }

class DemCli : public ::testing::Test {
protected:
    test::TempDir dir;
    std::string input = dir.file("dem.tif");
    void SetUp() override { test::writeFloatRaster(input, 65, 65, test::syntheticHeights(65, 65, 2500.0f)); }

    // Runs preprocessDem on `source` with `args` and returns its JSON report (exit 0 expected).
    nlohmann::json encode(const std::string& source, const std::string& args) {
        const std::string report = dir.file("r.json");
        const auto r = run(programPath("preprocessDem") + " -q " + shellQuoted(source) + " -o " + shellQuoted(dir.file("DEM.dat")) +
                           " --report " + shellQuoted(report) + " " + args);
        EXPECT_EQ(r.exitCode, 0) << args << "\n" << r.err;
        return r.exitCode == 0 ? nlohmann::json::parse(test::readFile(report)) : nlohmann::json{};
    }

    void expectError(const std::string& args, const std::string& mention) {
        const std::string out = dir.file("bad.dat");
        const auto r = run(programPath("preprocessDem") + " " + shellQuoted(input) + " -o " + shellQuoted(out) + " " + args);
        EXPECT_EQ(r.exitCode, 1) << args << "\n" << r.err;
        EXPECT_EQ(lines(r.err), 1u) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(mention), std::string::npos) << args << "\n" << r.err;
        EXPECT_FALSE(test::fileExists(out)) << args;
    }
};

TEST_F(DemCli, MaxErrorIsHalfTheScale) {
    const auto report = encode(input, "--tile-size 16 --root-tile-size 4 --max-error 0.05");
    EXPECT_FLOAT_EQ(report["header"]["scale"].get<float>(), 0.1f);
    for (const auto& l : report["levels"]) {
        EXPECT_LE(l["max_error"].get<double>(), 0.05 + 1e-3) << l;
    }
}

TEST_F(DemCli, ScaleAutoPicksTheSmallestFittingStepAndVerifies) {
    // Heights up to about 2800 do not fit at scale 0.05 (56000 steps at the root); 0.1 does.
    const auto report = encode(input, "--tile-size 16 --root-tile-size 4 --scale auto");
    const double scale = report["header"]["scale"].get<double>();
    EXPECT_NEAR(scale, 0.1, 1e-7);
    for (const auto& l : report["levels"]) {
        EXPECT_LE(l["max_abs_residual"].get<int>(), 32767);
    }
    const auto r = run(programPath("pyramid") + " verify " + shellQuoted(dir.file("DEM.dat")) + " --source " + shellQuoted(input));
    EXPECT_EQ(r.exitCode, 0) << r.out;
    // The next smaller step overflows, and the error names a scale that fits.
    const auto failed = run(programPath("preprocessDem") + " " + shellQuoted(input) + " -o " + shellQuoted(dir.file("s.dat")) +
                            " --tile-size 16 --root-tile-size 4 --scale 0.05");
    EXPECT_EQ(failed.exitCode, 1);
    EXPECT_NE(failed.err.find("overflow int16 at scale 0.05"), std::string::npos) << failed.err;
    EXPECT_NE(failed.err.find("--scale: "), std::string::npos) << failed.err;
    EXPECT_NE(failed.err.find("use 0."), std::string::npos) << failed.err;
    EXPECT_FALSE(test::fileExists(dir.file("s.dat")));
}

TEST_F(DemCli, MaxLevelResamplesAndBandSelectsAChannel) {
    // 65 samples with --max-level 5: 4 << 5 = 128 intervals, 129 samples, resampled.
    auto report = encode(input, "--tile-size 16 --root-tile-size 4 --max-level 5");
    EXPECT_EQ(report["header"]["max_level"], 5);
    EXPECT_EQ(report["finest_samples"], 129 * 129);
    EXPECT_NE(report["sampling"].get<std::string>().find("bilinear"), std::string::npos);
    // Two channels of 8-bit heights: band 2 is read by value (0..255, not 0..1).
    std::vector<uint16_t> px(33 * 33 * 2);
    for (size_t k = 0; k < px.size(); k += 2) {
        px[k] = 7;
        px[k + 1] = static_cast<uint16_t>(100 + (k / 2) % 33 * 4);
    }
    test::writeImage(dir.file("two.png"), 33, 33, 2, px, false);
    report = encode(dir.file("two.png"), "--tile-size 8 --root-tile-size 4 --band 2");
    EXPECT_EQ(report["input"]["type"], "uint8");
    EXPECT_EQ(report["input"]["band"], 2);
    EXPECT_GE(report["levels"][0]["max_abs_residual"].get<int>(), 100); // the root holds the heights
    const auto r = run(programPath("pyramid") + " verify --json " + shellQuoted(dir.file("DEM.dat")) + " --source " +
                       shellQuoted(dir.file("two.png")) + " --band 2");
    EXPECT_EQ(r.exitCode, 0) << r.out;
    EXPECT_EQ(nlohmann::json::parse(r.out)["levels"].back()["samples"], 33 * 33);
}

TEST_F(DemCli, DstMaxLevelCountsAsTheOriginalTools) {
    // The original preprocessDem(..., 4, 16, 2, ...): minLevel = log2(16 / 4) = 2, so its
    // dstMaxLevel 2 is the file's maxLevel 4, and the file is the one --max-level 4 writes.
    auto report = encode(input, "--tile-size 16 --root-tile-size 4 --dst-max-level 2");
    EXPECT_EQ(report["header"]["min_level"], 2);
    EXPECT_EQ(report["header"]["max_level"], 4);
    const std::string dst = test::readFile(dir.file("DEM.dat"));
    report = encode(input, "--tile-size 16 --root-tile-size 4 --max-level 4");
    EXPECT_EQ(test::readFile(dir.file("DEM.dat")), dst);
    // Both at once is a command-line error.
    const auto r = run(programPath("preprocessDem") + " " + shellQuoted(input) + " -o " + shellQuoted(dir.file("x.dat")) +
                       " --max-level 4 --dst-max-level 2");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    const auto help = run(programPath("preprocessDem") + " --help");
    EXPECT_NE(help.out.find("--dst-max-level"), std::string::npos);
    EXPECT_NE(help.out.find("minLevel + this"), std::string::npos);
}

TEST_F(DemCli, WarnsAboutTilesTheOriginalRuntimeCannotRead) {
    auto r = run(programPath("preprocessDem") + " " + shellQuoted(input) + " -o " + shellQuoted(dir.file("big.dat")) +
                 " --tile-size 256 --root-tile-size 64");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("warning: tiles of 261 samples"), std::string::npos) << r.err;
    r = run(programPath("preprocessDem") + " " + shellQuoted(input) + " -o " + shellQuoted(dir.file("small.dat")) +
            " --tile-size 16 --root-tile-size 4");
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

TEST_F(DemCli, ImpossibleValuesFailOnOneLine) {
    expectError("--tile-size 7", "--tile-size: 7 is not an even number from 2 to 8192");
    expectError("--tile-size 16 --root-tile-size 6", "--root-tile-size");
    expectError("--tile-size 12 --root-tile-size 3", "--root-tile-size: 3 is odd");
    expectError("--tile-size 16 --root-tile-size 4 --max-level 1", "--max-level");
    expectError("--tile-size 16 --root-tile-size 4 --max-level 25", "--max-level");
    expectError("--tile-size 16 --root-tile-size 4 --max-level 24", "tiles, more than");
    expectError("--scale -1", "--scale: must be a positive number, not -1");
    expectError("--max-error 0", "--max-error: must be a positive number, not 0");
    expectError("--tile-size 16 --root-tile-size 4 --dst-max-level 23", "--dst-max-level: 23 makes maxLevel");
    expectError("--scale fine", "--scale");
    expectError("--nodata low", "--nodata");
    expectError("--band 0", "--band");
    expectError("--threads -2", "--threads");
}

} // namespace
} // namespace pyramid
