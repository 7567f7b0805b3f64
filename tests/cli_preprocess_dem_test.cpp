// preprocessDem as a user runs it: a build verified, checked and reported, the same bytes again;
// verification against the wrong source fails; bad inputs and options fail with one line on
// stderr and nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::lines;
using test::programPath;
using test::run;
using test::shellQuoted;

class PreprocessDemCli : public ::testing::Test {
protected:
    test::TempDir dir;
    std::string input = dir.file("dem.tif");
    void SetUp() override { test::writeFloatRaster(input, 65, 65, test::syntheticHeights(65, 65)); }

    // Runs preprocessDem expecting failure: exit code `code`, one line on stderr mentioning
    // `mention`, and no file left in the output directory.
    void expectFailure(const std::string& args, int code, const std::string& mention) {
        const std::string outDir = dir.file("out");
        std::filesystem::create_directories(outDir);
        const auto r = run(programPath("preprocessDem") + " " + args + " -o " + shellQuoted(outDir + "/DEM.dat"));
        EXPECT_EQ(r.exitCode, code) << args << "\n" << r.err;
        EXPECT_EQ(lines(r.err), 1u) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(mention), std::string::npos) << args << "\n" << r.err;
        EXPECT_TRUE(std::filesystem::is_empty(outDir)) << args;
    }
};

TEST_F(PreprocessDemCli, BuildsVerifiesAndReports) {
    const std::string out = dir.file("DEM.dat");
    auto r = run(programPath("preprocessDem") + " " + shellQuoted(input) + " -o " + shellQuoted(out) +
                 " --tile-size 16 --root-tile-size 4 --scale 0.5 --quiet --report " + shellQuoted(dir.file("r.json")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, ""); // --quiet
    const auto report = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_EQ(report["header"]["max_level"], 4);
    EXPECT_EQ(report["header"]["scale"], 0.5);
    for (const auto& l : report["levels"]) {
        EXPECT_LE(l["max_error"].get<double>(), 0.25 + 1e-3);
    }
    r = run(programPath("pyramid") + " verify --json " + shellQuoted(out) + " --source " + shellQuoted(input));
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_TRUE(nlohmann::json::parse(r.out)["ok"].get<bool>());
    r = run(programPath("pyramid") + " check " + shellQuoted(out));
    EXPECT_EQ(r.exitCode, 0) << r.out;
    // Progress and a summary on stderr without --quiet; the same bytes again.
    r = run(programPath("pyramid") + " dem " + shellQuoted(input) + " -o " + shellQuoted(dir.file("again.dat")) +
            " --tile-size 16 --root-tile-size 4 --scale 0.5 --threads 1");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("100%"), std::string::npos) << r.err;
    EXPECT_EQ(test::readFile(out), test::readFile(dir.file("again.dat")));
}

TEST_F(PreprocessDemCli, VerifyFailsAgainstTheWrongSource) {
    const std::string out = dir.file("DEM.dat");
    ASSERT_EQ(run(programPath("preprocessDem") + " -q " + shellQuoted(input) + " -o " + shellQuoted(out)).exitCode, 0);
    std::vector<float> other = test::syntheticHeights(65, 65);
    other[65 * 30 + 30] += 10.0f;
    test::writeFloatRaster(dir.file("other.tif"), 65, 65, other);
    const auto r = run(programPath("pyramid") + " verify " + shellQuoted(out) + " --source " + shellQuoted(dir.file("other.tif")));
    EXPECT_EQ(r.exitCode, 1) << r.out;
    EXPECT_NE(r.out.find("BEYOND BOUND"), std::string::npos) << r.out;
}

TEST_F(PreprocessDemCli, BadInputFailsCleanly) {
    expectFailure(shellQuoted(dir.file("missing.tif")), 1, "missing.tif: no such file");
    {
        std::FILE* f = std::fopen(dir.file("junk.tif").c_str(), "wb");
        std::fputs("this is not an image", f);
        std::fclose(f);
    }
    expectFailure(shellQuoted(dir.file("junk.tif")), 1, "junk.tif");
    std::vector<float> withNan = test::syntheticHeights(65, 65);
    withNan[65 * 10 + 20] = std::nanf("");
    test::writeFloatRaster(dir.file("nan.tif"), 65, 65, withNan);
    expectFailure(shellQuoted(dir.file("nan.tif")), 1, "NaN height at column 20, row 10");
    expectFailure(shellQuoted(input) + " --tile-size 100 --root-tile-size 24", 1, "--root-tile-size");
    expectFailure(shellQuoted(input) + " --scale 0", 1, "--scale");
    expectFailure(shellQuoted(input) + " --band 2", 1, "--band");
    expectFailure(shellQuoted(input) + " --no-such-option", 2, "no-such-option");
    // A 16-bit PNG cut short: its header reads, its pixels fail once encoding has started.
    std::vector<uint16_t> heights(257 * 257);
    for (size_t k = 0; k < heights.size(); ++k) {
        heights[k] = static_cast<uint16_t>((k * 2654435761u) >> 16);
    }
    test::writeImage(dir.file("whole.png"), 257, 257, 1, heights, true);
    const std::string whole = test::readFile(dir.file("whole.png"));
    {
        std::FILE* f = std::fopen(dir.file("cut.png").c_str(), "wb");
        std::fwrite(whole.data(), 1, whole.size() / 2, f);
        std::fclose(f);
    }
    const std::string outDir = dir.file("out");
    const auto r = run(programPath("preprocessDem") + " " + shellQuoted(dir.file("cut.png")) + " -o " +
                       shellQuoted(outDir + "/DEM.dat"));
    EXPECT_EQ(r.exitCode, 1) << r.err;
    // One line, ours, naming the file and the problem.
    EXPECT_EQ(r.err, "preprocessDem: " + dir.file("cut.png") + ": cannot read: damaged or truncated PNG (Read Error)\n");
    EXPECT_TRUE(std::filesystem::is_empty(outDir));
}

} // namespace
} // namespace pyramid
