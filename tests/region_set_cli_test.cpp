// Region sets (doc/format.md 1.5) on the command line: the `pyramid` commands give a split DEM's
// (tests/support/region_sets.hpp) tiles, heights, verification, information and checks as the
// single file's, by its main file, index or directory, and refuse a broken set with one line;
// `pyramid check DIR` and `pyramid info DIR` take every pyramid under a directory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/paths.hpp"
#include "tests/support/region_sets.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::programPath;
using test::run;
using test::shellQuoted;
using test::SplitDem;

TEST(RegionSet, CommandsOnTheSetGiveTheSingleFilesResults) {
    SplitDem s;
    const std::string pyramid = programPath("pyramid");
    // The set named three ways (its main file, its index, its directory): each case below takes
    // the next one in turn, so that every way serves tiles and heights.
    const std::vector<std::string> spellings = {s.main, s.index, s.setDir};
    size_t turn = 0;
    // Tiles: elevations and stored residuals, from the deepest file.
    for (const auto& [l, tx, ty] : {std::tuple{6, 11, 19}, {4, 3, 5}, {1, 0, 0}, {0, 0, 0}, {3, 2, 3}}) {
        const std::string t = " " + std::to_string(l) + " " + std::to_string(tx) + " " + std::to_string(ty);
        for (const char* ext : {".f32", ".i16"}) {
            const std::string flag = std::string(ext) == ".i16" ? " --residual" : "";
            auto r = run(pyramid + " tile " + shellQuoted(s.single) + t + flag + " -o " + shellQuoted(s.dir.file("a") + ext));
            ASSERT_EQ(r.exitCode, 0) << r.err;
            const std::string& path = spellings[turn++ % spellings.size()];
            r = run(pyramid + " tile " + shellQuoted(path) + t + flag + " -o " + shellQuoted(s.dir.file("b") + ext));
            ASSERT_EQ(r.exitCode, 0) << r.err;
            EXPECT_EQ(test::readFile(s.dir.file("a") + ext), test::readFile(s.dir.file("b") + ext)) << path << t << flag;
        }
    }
    auto r = run(pyramid + " tile " + shellQuoted(s.setDir) + " 7 0 0 -o " + shellQuoted(s.dir.file("c.f32")));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("no tile (7,0,0) in any file of the set"), std::string::npos) << r.err;
    // Heights.
    for (const char* grid : {"0,0", "256,256", "100.5,37.25", "170,151"}) {
        const auto one = run(pyramid + " height " + shellQuoted(s.single) + " --grid " + grid + " --json");
        ASSERT_EQ(one.exitCode, 0) << one.err;
        const std::string& path = spellings[turn++ % spellings.size()];
        const auto many = run(pyramid + " height " + shellQuoted(path) + " --grid " + grid + " --json");
        ASSERT_EQ(many.exitCode, 0) << many.err;
        nlohmann::json a = nlohmann::json::parse(one.out), b = nlohmann::json::parse(many.out);
        a.erase("file");
        b.erase("file");
        EXPECT_EQ(a, b) << path << " " << grid;
    }
    // Verification against the source.
    const auto one = run(pyramid + " verify " + shellQuoted(s.single) + " --source " + shellQuoted(s.input) + " --json");
    ASSERT_EQ(one.exitCode, 0) << one.err;
    for (const std::string& path : {s.main, s.index, s.setDir}) {
        const auto many = run(pyramid + " verify " + shellQuoted(path) + " --source " + shellQuoted(s.input) + " --json");
        ASSERT_EQ(many.exitCode, 0) << many.err;
        nlohmann::json a = nlohmann::json::parse(one.out), b = nlohmann::json::parse(many.out);
        a.erase("file");
        b.erase("file");
        EXPECT_EQ(a, b) << path;
    }
    // Info: the files with their roots and sizes, and the totals.
    r = run(pyramid + " info " + shellQuoted(s.setDir) + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json info = nlohmann::json::parse(r.out);
    EXPECT_EQ(info["kind"], "residual");
    EXPECT_EQ(info["max_level"], 6);
    ASSERT_EQ(info["files"].size(), 18u);
    EXPECT_EQ(info["files"][0]["root"], nlohmann::json({0, 0, 0}));
    EXPECT_EQ(info["files"][17]["root"], nlohmann::json({5, 5, 9}));
    EXPECT_EQ(info["files"][17]["levels"], nlohmann::json({5, 6}));
    uint64_t bytes = 0;
    for (const auto& f : info["files"]) {
        bytes += fs::file_size(f["file"].get<std::string>());
    }
    EXPECT_EQ(info["totals"]["file_bytes"], bytes);
    EXPECT_EQ(info["totals"]["files"], 18);
    r = run(pyramid + " info " + shellQuoted(s.main));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("residual pyramid set, 18 files"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("(5,5,9)"), std::string::npos) << r.out;
    // Check: every file, and the set's rules.
    r = run(pyramid + " check " + shellQuoted(s.index) + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
    const nlohmann::json check = nlohmann::json::parse(r.out);
    EXPECT_EQ(check["ok"], true);
    EXPECT_EQ(check["files"].size(), 18u);
    int64_t tiles = 0;
    for (const auto& f : check["files"]) {
        tiles += f["tiles_checked"].get<int64_t>();
    }
    EXPECT_EQ(check["tiles_checked"], tiles);
    fs::remove(s.nested);
    r = run(pyramid + " check " + shellQuoted(s.setDir));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find(s.nested + ": no such file (listed in "), std::string::npos) << r.err;
    r = run(pyramid + " check " + shellQuoted(s.main) + " --json");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(nlohmann::json::parse(r.out)["ok"], false);
    // The other commands refuse a broken set with that one line.
    for (const std::string& command : {std::string(" info "), std::string(" height ")}) {
        r = run(pyramid + command + shellQuoted(s.setDir) + (command == " height " ? " --grid 1,1" : ""));
        EXPECT_EQ(r.exitCode, 1) << command;
        EXPECT_EQ(r.err, "pyramid: " + s.nested + ": no such file (listed in " + s.index + ")\n") << command;
    }
    r = run(pyramid + " verify " + shellQuoted(s.index) + " --source " + shellQuoted(s.input));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find(s.nested + ": no such file"), std::string::npos) << r.err;
    // A file alone is as before.
    r = run(pyramid + " check " + shellQuoted(s.single));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find(s.single + ": residual, "), std::string::npos) << r.out;
}

// `pyramid check DIR` (and `pyramid info DIR`) on a directory that is not one set alone takes
// every pyramid under it, as each would be taken alone: every region set by its index (its files counted once, not again
// as files alone), and every other *.dat file, in subdirectories too; one broken file fails the
// whole, named in the one line on stderr.
TEST(RegionSet, CheckAndInfoOfADirectoryTakeEveryPyramidUnderIt) {
    SplitDem s;
    const std::string pyramid = programPath("pyramid");
    const std::string top = s.dir.file("");
    auto r = run(pyramid + " check " + shellQuoted(top) + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["ok"], true);
    ASSERT_EQ(j["pyramids"].size(), 2u);
    EXPECT_EQ(j["pyramids"][0]["set"], s.index);
    EXPECT_EQ(j["pyramids"][0]["files"].size(), 18u);
    EXPECT_EQ(j["pyramids"][1]["file"], s.single);
    const auto alone = [&](const std::string& path) {
        const auto one = run(pyramid + " check " + shellQuoted(path) + " --json");
        EXPECT_EQ(one.exitCode, 0) << one.err;
        return nlohmann::json::parse(one.out)["tiles_checked"].get<int64_t>();
    };
    EXPECT_EQ(j["tiles_checked"], alone(s.index) + alone(s.single));
    r = run(pyramid + " check " + shellQuoted(top));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find(top + ": 2 pyramids (1 region set), "), std::string::npos) << r.out;
    // `pyramid info` takes the directory the same way: each pyramid's information, and the totals.
    r = run(pyramid + " info " + shellQuoted(top) + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["pyramids"].size(), 2u);
    EXPECT_EQ(j["pyramids"][0]["set"], s.index);
    EXPECT_EQ(j["pyramids"][1]["file"], s.single);
    EXPECT_EQ(j["totals"]["files"], 19);
    EXPECT_EQ(j["totals"]["file_bytes"],
              j["pyramids"][0]["totals"]["file_bytes"].get<uint64_t>() + fs::file_size(s.single));
    r = run(pyramid + " info " + shellQuoted(top));
    EXPECT_NE(r.out.find(top + ": 2 pyramids (1 region set), 19 files, "), std::string::npos) << r.out;

    // A file the set does not list, though named like its regions, is checked alone; a broken
    // one fails the directory.
    fs::copy_file(s.nested, s.dir.file("set/DEM-L5-4-9.dat"));
    std::string bytes = test::readFile(s.single);
    bytes.resize(bytes.size() - 7);
    {
        std::ofstream out(s.dir.file("single/cut.dat"), std::ios::binary);
        out << bytes;
    }
    r = run(pyramid + " check " + shellQuoted(top) + " --json");
    EXPECT_EQ(r.exitCode, 1);
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["ok"], false);
    ASSERT_EQ(j["pyramids"].size(), 4u);
    EXPECT_EQ(j["pyramids"][1]["file"], s.dir.file("set/DEM-L5-4-9.dat"));
    EXPECT_EQ(j["pyramids"][1]["ok"], true);
    EXPECT_EQ(j["pyramids"][2]["file"], s.single);
    EXPECT_EQ(j["pyramids"][3]["file"], s.dir.file("single/cut.dat"));
    EXPECT_EQ(j["pyramids"][3]["ok"], false);
    EXPECT_EQ(r.err.rfind("pyramid: " + s.dir.file("single/cut.dat") + ": ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;

    // A directory holding no pyramid: one line, exit 1.
    fs::create_directories(s.dir.file("nothing"));
    for (const char* command : {" check ", " info "}) {
        r = run(pyramid + command + shellQuoted(s.dir.file("nothing")));
        EXPECT_EQ(r.exitCode, 1) << command;
        EXPECT_NE(r.err.find("no pyramid (a *.dat file or a *.regions.json index) in this directory"),
                  std::string::npos)
            << r.err;
    }
}

} // namespace
} // namespace pyramid
