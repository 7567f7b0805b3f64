// The `pyramid` inspection commands as a user runs them: info and check of the original files,
// a broken file failing with one line, and one spelling of JSON output, --report FILE|-, in every
// command.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::programPath;
using test::run;
using test::shellQuoted;

TEST(PyramidInfo, DescribesTheOriginalFiles) {
    const auto r = run(programPath("pyramid") + " info --json " + shellQuoted(test::dataPath("proland/DEM.dat")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["kind"], "residual");
    EXPECT_EQ(j["header"]["min_level"], 3);
    EXPECT_EQ(j["header"]["tile_size"], 192);
    EXPECT_EQ(j["tiles"], 24);
    EXPECT_EQ(j["encodings"]["deflate-legacy"], 24);
    EXPECT_EQ(j["levels"][5]["tiles"], 16);
    EXPECT_EQ(j["levels"][0]["tile_side"], 29);
    const auto o = nlohmann::json::parse(run(programPath("pyramid") + " info --json " +
                                             shellQuoted(test::dataPath("proland/RGB.dat"))).out);
    EXPECT_EQ(o["kind"], "ortho");
    EXPECT_EQ(o["header"]["border"], 2);
    EXPECT_EQ(o["header"]["channels"], 4);
}

TEST(PyramidCheck, PassesGoodFilesAndFailsBrokenOnes) {
    for (const char* f : {"proland/DEM.dat", "proland/RGB.dat"}) {
        const auto r = run(programPath("pyramid") + " check --json " + shellQuoted(test::dataPath(f)));
        EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
        EXPECT_TRUE(nlohmann::json::parse(r.out)["ok"].get<bool>());
    }
    test::TempDir dir;
    std::string bytes = test::readFile(test::dataPath("proland/DEM.dat"));
    bytes[28 + 8 * 24 + 200] ^= 0x5a; // corrupt the root tile's compressed data
    {
        std::FILE* f = std::fopen(dir.file("bad.dat").c_str(), "wb");
        std::fwrite(bytes.data(), 1, bytes.size(), f);
        std::fclose(f);
    }
    const auto r = run(programPath("pyramid") + " check " + shellQuoted(dir.file("bad.dat")));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.out.find("tile (0,0,0)"), std::string::npos) << r.out;
    // The reason, on one line of stderr as for every failure: the program, the file, the tile.
    const std::string reason = "pyramid: " + dir.file("bad.dat") + ": ";
    EXPECT_EQ(r.err.rfind(reason, 0), 0u) << r.err;
    EXPECT_NE(r.err.find("tile (0,0,0)"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    // --json keeps the report on stdout, whole, and says the same on stderr.
    const auto j = run(programPath("pyramid") + " check --json " + shellQuoted(dir.file("bad.dat")));
    EXPECT_EQ(j.exitCode, 1);
    EXPECT_FALSE(nlohmann::json::parse(j.out)["ok"].get<bool>());
    EXPECT_EQ(j.err, r.err);
    // A file cut short fails to open: the reason names it, and nothing else is on stderr.
    {
        std::FILE* f = std::fopen(dir.file("short.dat").c_str(), "wb");
        std::fwrite(bytes.data(), 1, 40, f);
        std::fclose(f);
    }
    const auto s = run(programPath("pyramid") + " check " + shellQuoted(dir.file("short.dat")));
    EXPECT_EQ(s.exitCode, 1);
    EXPECT_EQ(s.err.rfind("pyramid: " + dir.file("short.dat") + ": ", 0), 0u) << s.err;
    EXPECT_EQ(s.err.find('\n'), s.err.size() - 1) << s.err;
    // A good file prints nothing on stderr.
    EXPECT_EQ(run(programPath("pyramid") + " check " + shellQuoted(test::dataPath("proland/DEM.dat"))).err, "");
}

// JSON output has one spelling, --report FILE|-, in every command; --json is --report -.
// The inspection commands print their text on stdout unless the JSON goes there; the two
// spellings give the same JSON, and naming both is a usage error.
TEST(Report, OneSpellingForEveryCommand) {
    test::TempDir dir;
    const std::string dem = shellQuoted(test::dataPath("proland/DEM.dat"));
    for (const std::string command : {"info", "check"}) {
        const std::string base = programPath("pyramid") + " " + command + " " + dem;
        const auto alias = run(base + " --json");
        ASSERT_EQ(alias.exitCode, 0) << alias.err;
        const auto dash = run(base + " --report -");
        ASSERT_EQ(dash.exitCode, 0) << dash.err;
        EXPECT_EQ(nlohmann::json::parse(dash.out), nlohmann::json::parse(alias.out)) << command;
        const std::string file = dir.file(command + ".json");
        const auto toFile = run(base + " --report " + shellQuoted(file));
        ASSERT_EQ(toFile.exitCode, 0) << toFile.err;
        EXPECT_EQ(nlohmann::json::parse(test::readFile(file)), nlohmann::json::parse(alias.out)) << command;
        EXPECT_FALSE(nlohmann::json::accept(toFile.out)) << "the text stays on stdout";
        EXPECT_FALSE(toFile.out.empty());
        EXPECT_EQ(run(base + " --json --report " + shellQuoted(dir.file("both.json"))).exitCode, 2) << command;
        EXPECT_FALSE(test::fileExists(dir.file("both.json")));
    }
    // A builder: --json prints the report that --report FILE writes.
    test::writeFloatRaster(dir.file("in.tif"), 65, 65, test::syntheticHeights(65, 65));
    const std::string build = programPath("preprocessDem") + " -q " + shellQuoted(dir.file("in.tif")) + " -o ";
    const auto alias = run(build + shellQuoted(dir.file("a/DEM.dat")) + " --json");
    ASSERT_EQ(alias.exitCode, 0) << alias.err;
    ASSERT_EQ(run(build + shellQuoted(dir.file("b/DEM.dat")) + " --report " + shellQuoted(dir.file("b.json"))).exitCode, 0);
    auto printed = nlohmann::json::parse(alias.out), written = nlohmann::json::parse(test::readFile(dir.file("b.json")));
    EXPECT_EQ(printed["levels"], written["levels"]);
    EXPECT_EQ(printed["bytes"], written["bytes"]);
}

} // namespace
} // namespace pyramid
