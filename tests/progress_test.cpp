// Progress on stderr (--progress): JSON lines that parse, rise steadily and end at 100 % with
// done == total, from the builders and from check and verify; a line every 5 % when stderr is not a terminal; nothing with none or --quiet;
// an unknown mode refused as a usage error.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::TempDir;

std::vector<std::string> linesOf(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        lines.push_back(line);
    }
    return lines;
}

struct Dem {
    TempDir dir;
    std::string command;
    Dem() {
        test::writeFloatRaster(dir.file("in.tif"), 257, 257, test::syntheticHeights(257, 257, 500.0f));
        command = test::programPath("preprocessDem") + " " + dir.file("in.tif") +
                  " --tile-size 32 --root-tile-size 8 --scale 0.25 --threads 1 -o " + dir.file("DEM.dat");
    }
};

// The JSON progress lines of `err` (other lines skipped) under `label`: they must parse, rise
// strictly and end at done == total, 100 %; returns the total.
int64_t checkJsonProgress(const std::string& err, const std::string& label) {
    double percent = -1.0;
    int64_t done = -1, total = 0;
    int lines = 0;
    for (const std::string& line : linesOf(err)) {
        if (line.empty() || line[0] != '{') {
            continue; // the summary
        }
        const nlohmann::json j = nlohmann::json::parse(line);
        EXPECT_EQ(j.at("progress"), label);
        EXPECT_GE(j.at("percent").get<double>(), percent) << line;
        EXPECT_GT(j.at("done").get<int64_t>(), done) << line;
        percent = j.at("percent").get<double>();
        done = j.at("done").get<int64_t>();
        total = j.at("total").get<int64_t>();
        EXPECT_TRUE(j.contains("rate") && j.contains("eta_seconds")) << line;
        ++lines;
    }
    EXPECT_GE(lines, 2) << err;
    EXPECT_EQ(percent, 100.0);
    EXPECT_EQ(done, total);
    return total;
}

constexpr int64_t kDemTiles = 2 + (256 - 1) / 3; // levels 0 and 1 single, then 1, 4, 16, 64

TEST(Progress, JsonLinesRiseAndEndAtTheTotal) {
    Dem d;
    const test::RunResult r = test::run(d.command + " --progress json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(checkJsonProgress(r.err, "preprocessDem"), kDemTiles) << "the pyramid's tiles";
}

// check and verify count the tiles they decode or compare, from several threads (the lines
// still rise), when asked; in the auto mode off a terminal they say nothing on stderr, which a
// script reads for the one failure line.
TEST(Progress, CheckAndVerifyCountTheirTilesWhenAsked) {
    Dem d;
    ASSERT_EQ(test::run(d.command + " -q").exitCode, 0);
    const std::string dem = d.dir.file("DEM.dat");
    const std::string check = test::programPath("pyramid") + " check " + dem + " --threads 2";
    const test::RunResult json = test::run(check + " --progress json");
    ASSERT_EQ(json.exitCode, 0) << json.err;
    EXPECT_EQ(checkJsonProgress(json.err, dem), kDemTiles);
    const test::RunResult plain = test::run(check);
    ASSERT_EQ(plain.exitCode, 0) << plain.err;
    EXPECT_EQ(plain.err, "");
    EXPECT_EQ(test::run(check + " --progress json -q").err, "");

    const std::string verify =
        test::programPath("pyramid") + " verify " + dem + " --source " + d.dir.file("in.tif") + " --threads 2";
    const test::RunResult verified = test::run(verify + " --progress json");
    ASSERT_EQ(verified.exitCode, 0) << verified.err;
    EXPECT_EQ(checkJsonProgress(verified.err, dem), kDemTiles);
    EXPECT_EQ(test::run(verify).err, "");
    const test::RunResult lines = test::run(verify + " --progress lines");
    EXPECT_NE(lines.err.find(dem + ": 100% (" + std::to_string(kDemTiles) + "/"), std::string::npos) << lines.err;
}

TEST(Progress, LinesEveryFivePercentNoneOrQuietSayNothing) {
    Dem d;
    const test::RunResult lines = test::run(d.command + " --progress lines");
    ASSERT_EQ(lines.exitCode, 0) << lines.err;
    int shown = 0;
    for (const std::string& line : linesOf(lines.err)) {
        if (line.rfind("preprocessDem: ", 0) == 0 && line.find('%') != std::string::npos) {
            ++shown;
        }
    }
    EXPECT_GE(shown, 5);
    EXPECT_LE(shown, 21);
    EXPECT_NE(lines.err.find("preprocessDem: 100% ("), std::string::npos) << lines.err;
    for (const std::string quiet : {" --progress none", " -q --progress json"}) {
        const test::RunResult r = test::run(d.command + quiet);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_EQ(r.err.find('%'), std::string::npos) << quiet << ": " << r.err;
        EXPECT_EQ(r.err.find("\"progress\""), std::string::npos) << quiet << ": " << r.err;
    }
    const test::RunResult bad = test::run(d.command + " --progress loud");
    EXPECT_EQ(bad.exitCode, 2) << bad.err;
    EXPECT_NE(bad.err.find("'loud' is not auto, bar, lines, json or none"), std::string::npos) << bad.err;
}

} // namespace
} // namespace pyramid
