// Region sets (doc/format.md 1.5): a DEM encoded as one file and split here into a main file and
// region files (one of them nested in another) reconstructs the single file bit for bit through
// the set producers and the `pyramid` commands, by its main file, index or directory; the index
// round-trips; every rule of a set rejects a set that breaks it, with its message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/runtime/height_query.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "libpyramid/verify/ortho_verify.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::programPath;
using test::run;

std::string shellQuoted(const std::string& s) { return "'" + s + "'"; }

// Copies the tiles of `single` into a new file at `path` with header `h`: tile (l, x, y) of the new
// file is tile (rootLevel + l, rootTx 2^l + x, rootTy 2^l + y) of the single file.
void copyResidual(const ResidualFileReader& single, const std::string& path, const ResidualHeader& h) {
    ResidualFileWriter w(path, h);
    for (int l = 0; l <= h.maxLevel; ++l) {
        const int64_t side = h.tilesPerSide(l);
        for (int64_t y = 0; y < side; ++y) {
            for (int64_t x = 0; x < side; ++x) {
                const int ax = static_cast<int>((int64_t{h.rootTx} << l) + x);
                const int ay = static_cast<int>((int64_t{h.rootTy} << l) + y);
                w.writeTileBytes(l, static_cast<int>(x), static_cast<int>(y),
                                 single.readTileBytes(h.rootLevel + l, ax, ay));
            }
        }
    }
    w.commit();
}

ResidualHeader regionHeader(const ResidualHeader& single, RegionRoot root, int maxLevel) {
    ResidualHeader h = single;
    h.minLevel = 0;
    h.maxLevel = maxLevel;
    h.rootLevel = root.level;
    h.rootTx = root.tx;
    h.rootTy = root.ty;
    return h;
}

// A 257 x 257 DEM (tile size 8, minLevel 1, levels 0..6) encoded as DEM.dat in `single/`, and the
// same pyramid split in `set/`: the main file holds levels 0..2, the 16 tiles of level 3 root
// region files down to level 6, and region (5,5,9), nested in region (3,1,2), holds that
// subtree's levels 5..6 again: the deepest file serves them.
struct SplitDem {
    test::TempDir dir;
    std::string input = dir.file("dem.tif");
    std::string single = dir.file("single/DEM.dat");
    std::string setDir = dir.file("set");
    std::string main = dir.file("set/DEM.dat");
    std::string index = dir.file("set/DEM.dat.regions.json");
    std::string nested = dir.file("set/DEM-L5-5-9.dat");
    ResidualHeader header;
    std::vector<RegionRoot> roots;

    SplitDem() {
        fs::create_directories(dir.file("single"));
        fs::create_directories(setDir);
        test::writeFloatRaster(input, 257, 257, test::syntheticHeights(257, 257));
        DemEncodeOptions o;
        o.tileSize = 8;
        o.rootTileSize = 4;
        o.scale = 0.25;
        header = encodeDem(input, single, o).header;
        const auto reader = ResidualFileReader::open(single);
        ResidualHeader m = header;
        m.maxLevel = 2;
        copyResidual(*reader, main, m);
        for (int ty = 0; ty < 4; ++ty) {
            for (int tx = 0; tx < 4; ++tx) {
                const RegionRoot r{3, tx, ty};
                copyResidual(*reader, regionFilePath(main, r), regionHeader(header, r, header.maxLevel - 3));
                roots.push_back(r);
            }
        }
        const RegionRoot n{5, 5, 9};
        copyResidual(*reader, nested, regionHeader(header, n, 1));
        roots.push_back(n);
        writeRegionIndex(index, makeRegionIndex(main, PyramidKind::Residual, roots));
    }
};

TEST(RegionIndex, NamesRoundTripAndResolution) {
    EXPECT_EQ(regionIndexPath("out/DEM.dat"), "out/DEM.dat.regions.json");
    EXPECT_EQ(regionFilePath("out/DEM.dat", {6, 12, 40}), "out/DEM-L6-12-40.dat");
    EXPECT_EQ(regionFilePath("RGB.dat", {1, 0, 1}), "RGB-L1-0-1.dat");
    // The names parse back to their main file and root; no other name does.
    for (const auto& [main, root] : std::vector<std::pair<std::string, RegionRoot>>{
             {"out/DEM.dat", {6, 12, 40}}, {"RGB3.dat", {1, 0, 1}}, {"a-L1-0-1.b.dat", {30, 0, (1 << 30) - 1}},
             {"x/DEM", {2, 3, 3}}}) {
        const auto parsed = parseRegionFilePath(regionFilePath(main, root));
        ASSERT_TRUE(parsed) << main;
        EXPECT_EQ(parsed->mainFile, main);
        EXPECT_EQ(parsed->root, root);
    }
    for (const std::string name : {"RGB.dat", "RGB3.dat", "RGB-L0-0-0.dat", "RGB-L1-2-0.dat", "RGB-L1-01-0.dat",
                                   "RGB-L31-0-0.dat", "-L1-0-0.dat", "RGB-1-0-0.dat", "RGB-L1-0.dat", "RGB-L1-0-1-.dat",
                                   "RGB-L1--0-1.dat", "RGB-L1-0-+1.dat", "RGB-L99999999999-0-0.dat"}) {
        EXPECT_FALSE(parseRegionFilePath("out/" + name)) << name;
    }
    const RegionIndex index = makeRegionIndex("out/DEM.dat", PyramidKind::Ortho, {{7, 1, 2}, {6, 12, 40}, {6, 3, 40}});
    EXPECT_EQ(index.main, "DEM.dat");
    ASSERT_EQ(index.regions.size(), 3u);
    EXPECT_EQ(index.regions[0].file, "DEM-L6-3-40.dat"); // sorted by (level, tx, ty)
    EXPECT_EQ(index.regions[2].file, "DEM-L7-1-2.dat");
    const std::string text = formatRegionIndex(index);
    const nlohmann::json j = nlohmann::json::parse(text);
    EXPECT_EQ(j["format"], "libpyramid region set");
    EXPECT_EQ(j["version"], 1);
    EXPECT_EQ(j["kind"], "ortho");
    EXPECT_EQ(j["regions"][1]["root"], nlohmann::json({6, 12, 40}));
    const RegionIndex back = parseRegionIndex(text, "x.json");
    EXPECT_EQ(back.kind, PyramidKind::Ortho);
    EXPECT_EQ(back.main, "DEM.dat");
    ASSERT_EQ(back.regions.size(), 3u);
    EXPECT_EQ(back.regions[1].root, (RegionRoot{6, 12, 40}));
    EXPECT_EQ(formatRegionIndex(back), text);

    const auto refuses = [](const std::string& json, const std::string& words) {
        try {
            parseRegionIndex(json, "I.json");
            ADD_FAILURE() << "accepted " << json;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("I.json: "), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
    };
    refuses("{", "not JSON");
    refuses(R"({"format": "other"})", "not a region set index");
    refuses(R"({"format": "libpyramid region set", "version": 2, "kind": "ortho", "main": "a", "regions": []})",
            "version 2");
    refuses(R"({"format": "libpyramid region set", "version": 1, "kind": "dem", "main": "a", "regions": []})",
            "unknown kind 'dem'");
    refuses(R"({"format": "libpyramid region set", "version": 1, "kind": "ortho", "main": "a",
               "regions": [{"file": "b", "root": [1, 2]}]})",
            "not three whole numbers");
    refuses(R"({"format": "libpyramid region set", "version": 1, "kind": "ortho", "main": "a",
               "regions": [{"file": "b", "root": [2, 4, 0]}]})",
            "outside its level");
    refuses(R"({"format": "libpyramid region set", "version": 1, "kind": "ortho", "main": "a",
               "regions": [{"file": "b", "root": [0, 0, 0]}]})",
            "level must be 1 to 30");
    refuses(R"({"format": "libpyramid region set", "version": 1, "kind": "ortho", "main": "",
               "regions": []})",
            "main file's name is empty");
    // Every file within the index's directory: no absolute path, nothing that climbs out of it.
    refuses(R"({"format": "libpyramid region set", "version": 1, "kind": "ortho", "main": "a",
               "regions": [{"file": "/tmp/b.dat", "root": [1, 0, 0]}]})",
            "'/tmp/b.dat' is not a path within the index's directory");
    refuses(R"({"format": "libpyramid region set", "version": 1, "kind": "ortho", "main": "a",
               "regions": [{"file": "sub/../../b.dat", "root": [1, 0, 0]}]})",
            "is not a path within the index's directory");
    refuses(R"({"format": "libpyramid region set", "version": 1, "kind": "ortho", "main": "../a.dat",
               "regions": []})",
            "main file '../a.dat' is not a path within");
}

TEST(RegionSet, ResolvesByMainFileIndexAndDirectory) {
    SplitDem s;
    for (const std::string& path : {s.main, s.index, s.setDir}) {
        SCOPED_TRACE(path);
        const PyramidSet set = openPyramidSet(path);
        EXPECT_EQ(set.index, path == s.setDir ? (fs::path(s.setDir) / "DEM.dat.regions.json").string() : s.index);
        EXPECT_EQ(fs::path(set.main).filename(), "DEM.dat");
        EXPECT_TRUE(fs::equivalent(set.main, s.main));
        EXPECT_EQ(set.kind, PyramidKind::Residual);
        EXPECT_EQ(set.regions.size(), 17u);
        EXPECT_EQ(setMaxLevel(set), 6);
    }
    // The single file: alone, no index.
    const PyramidSet alone = openPyramidSet(s.single);
    EXPECT_TRUE(alone.index.empty());
    EXPECT_TRUE(alone.regions.empty());
    EXPECT_EQ(alone.main, s.single);
    // A directory with no index, or two.
    EXPECT_THROW(
        {
            try {
                resolvePyramidSet(s.dir.file("single"));
            } catch (const Error& e) {
                EXPECT_NE(std::string(e.what()).find("no region set index"), std::string::npos) << e.what();
                throw;
            }
        },
        Error);
    fs::copy_file(s.index, s.dir.file("set/Other.dat.regions.json"));
    try {
        resolvePyramidSet(s.setDir);
        ADD_FAILURE() << "two indexes accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("DEM.dat.regions.json, Other.dat.regions.json"), std::string::npos)
            << e.what();
    }
}

TEST(RegionSet, ElevationsAndHeightsEqualTheSingleFileBitForBit) {
    SplitDem s;
    const PyramidSet set = openPyramidSet(s.setDir);
    // The nested region serves its tiles (the deepest file holding them).
    EXPECT_EQ(storedResidualTile(set, 6, 11, 19).file, s.nested);
    EXPECT_EQ(storedResidualTile(set, 5, 5, 9).file, s.nested);
    EXPECT_EQ(storedResidualTile(set, 6, 9, 19).file, regionFilePath(s.main, {3, 1, 2}));
    EXPECT_EQ(storedResidualTile(set, 2, 1, 1).file, s.main);
    EXPECT_EQ(storedResidualTile(set, 6, 11, 19).residuals, ResidualFileReader::open(s.single)->readTile(6, 11, 19));
    for (int l = 0; l <= s.header.maxLevel; ++l) {
        const FileLevelProducer one = makeFileLevelProducer(s.single, l);
        const FileLevelProducer many = makeSetLevelProducer(l % 2 ? s.main : s.index, l);
        ASSERT_EQ(one.delta, many.delta);
        ASSERT_EQ(one.n, many.n);
        const int side = l < s.header.minLevel ? 1 : 1 << (l - s.header.minLevel);
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                const auto a = one.fileTile(l, tx, ty);
                const auto b = many.fileTile(l, tx, ty);
                ASSERT_EQ(a->zf.size(), b->zf.size());
                ASSERT_EQ(std::memcmp(a->zf.data(), b->zf.data(), a->zf.size() * sizeof(float)), 0)
                    << "tile (" << l << "," << tx << "," << ty << ")";
            }
        }
    }
    // Elevation tiles of another size, through the C++ producer opened on the set.
    ElevationProducerOptions eo;
    eo.tileSize = 4;
    auto fromSet = openElevationSet(s.setDir, eo);
    ResidualProducerOptions ro;
    ro.delta = elevationDelta(s.header, 4);
    ElevationProducer fromFile(std::make_shared<ResidualProducer>(s.single, std::vector<std::string>{}, ro), eo);
    EXPECT_EQ(fromSet->maxLevel(), fromFile.maxLevel());
    for (const auto& [l, tx, ty] : {std::tuple{5, 10, 18}, {5, 31, 0}, {4, 7, 7}, {2, 1, 3}}) {
        EXPECT_EQ(fromSet->tile(l, tx, ty)->zf, fromFile.tile(l, tx, ty)->zf) << l << "," << tx << "," << ty;
    }
    for (const auto& [u, v] : {std::pair{0.0, 0.0}, {1.0, 1.0}, {0.3, 0.61}, {0.33, 0.59}, {0.9, 0.05}}) {
        const PointHeight a = fileHeightAt(s.single, u, v);
        const PointHeight b = setHeightAt(s.main, u, v);
        EXPECT_EQ(a.height, b.height) << u << "," << v;
        EXPECT_EQ(a.level, b.level);
        EXPECT_EQ(a.tx, b.tx);
        EXPECT_EQ(a.ty, b.ty);
    }
    // Verification of the whole set against the source: the single file's report.
    const DemVerifyReport one = verifyDem(s.single, s.input, {});
    const DemVerifyReport many = verifyDem(s.setDir, s.input, {});
    EXPECT_TRUE(many.ok());
    nlohmann::json a = toJson(one), b = toJson(many);
    a.erase("file");
    b.erase("file");
    EXPECT_EQ(a, b);
    EXPECT_EQ(many.levels.size(), 7u);
    // A region holding another subtree's tiles: the set no longer matches its source.
    const std::string r = regionFilePath(s.main, {3, 1, 2});
    fs::remove(r);
    copyResidual(*ResidualFileReader::open(s.single), r + ".tmp", regionHeader(s.header, {3, 2, 1}, 3));
    {
        // The header says (3,1,2), the tiles are (3,2,1)'s.
        ResidualHeader h = regionHeader(s.header, {3, 1, 2}, 3);
        const auto wrong = ResidualFileReader::open(r + ".tmp");
        ResidualFileWriter w(r, h);
        for (int l = 0; l <= 3; ++l) {
            for (int y = 0; y < (1 << l); ++y) {
                for (int x = 0; x < (1 << l); ++x) {
                    w.writeTileBytes(l, x, y, wrong->readTileBytes(l, x, y));
                }
            }
        }
        w.commit();
    }
    fs::remove(r + ".tmp");
    EXPECT_FALSE(verifyDem(s.main, s.input, {}).ok());
}

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

// Rewrites the set's index with `roots` (files named after them) and returns the set's problems.
std::vector<std::string> problemsWith(const SplitDem& s, const std::vector<RegionRoot>& roots) {
    writeRegionIndex(s.index, makeRegionIndex(s.main, PyramidKind::Residual, roots));
    return pyramidSetProblems(resolvePyramidSet(s.index));
}

void expectProblem(const std::vector<std::string>& problems, const std::string& file, const std::string& words) {
    ASSERT_FALSE(problems.empty()) << "no problem: expected " << words;
    bool found = false;
    for (const std::string& p : problems) {
        found = found || (p.rfind(file + ": ", 0) == 0 && p.find(words) != std::string::npos);
    }
    EXPECT_TRUE(found) << "expected '" << file << ": ..." << words << "', got: " << problems.front();
}

TEST(RegionSet, EveryRuleRejectsASetThatBreaksIt) {
    SplitDem s;
    EXPECT_TRUE(pyramidSetProblems(resolvePyramidSet(s.index)).empty());
    const auto reader = ResidualFileReader::open(s.single);
    std::vector<RegionRoot> roots = s.roots;
    // A listed file is missing.
    {
        auto more = roots;
        more.push_back({4, 0, 0});
        expectProblem(problemsWith(s, more), regionFilePath(s.main, {4, 0, 0}), "no such file (listed in");
    }
    // A region holds the other kind of pyramid.
    {
        OrthoHeader oh;
        oh.maxLevel = 0;
        oh.tileSize = 4;
        oh.channels = 1;
        oh.rootLevel = 4;
        OrthoFileWriter w(regionFilePath(s.main, {4, 0, 0}), oh);
        w.writeTileBytes(0, 0, 0, std::vector<uint8_t>(16, 7));
        w.commit();
        auto more = roots;
        more.push_back({4, 0, 0});
        expectProblem(problemsWith(s, more), regionFilePath(s.main, {4, 0, 0}),
                      "holds an ortho pyramid; the set is residual");
    }
    const std::string r40 = regionFilePath(s.main, {4, 0, 0});
    const auto withRegion = [&](const ResidualHeader& h, RegionRoot listed) {
        fs::remove(r40);
        copyResidual(*reader, r40, h);
        auto more = roots;
        more.push_back(listed);
        // The file is named after `listed`: rename when they differ.
        const std::string named = regionFilePath(s.main, listed);
        if (named != r40) {
            fs::rename(r40, named);
        }
        return problemsWith(s, more);
    };
    const ResidualHeader good = regionHeader(s.header, {4, 0, 0}, 2);
    EXPECT_TRUE(withRegion(good, {4, 0, 0}).empty());
    {
        // minLevel 1 (which the format refuses for a region file: its reader says so).
        withRegion(good, {4, 0, 0});
        {
            std::fstream f(r40, std::ios::in | std::ios::out | std::ios::binary);
            const int32_t one = 1;
            f.write(reinterpret_cast<const char*>(&one), sizeof one);
        }
        expectProblem(pyramidSetProblems(resolvePyramidSet(s.index)), r40, "minLevel");
    }
    {
        ResidualHeader h = good;
        h.scale = 0.5f;
        expectProblem(withRegion(h, {4, 0, 0}), r40, "scale 0.5, the main file's is 0.25");
    }
    {
        // Another tile size: rebuilt from a 16-sample pyramid is not possible by copying; a
        // header whose tiles are written fresh instead.
        ResidualHeader h = good;
        h.tileSize = 4;
        h.maxLevel = 0;
        fs::remove(r40);
        ResidualFileWriter w(r40, h);
        w.writeTile(0, 0, 0, std::vector<int16_t>(static_cast<size_t>(h.tileSamples(0) * h.tileSamples(0)), 0));
        w.commit();
        auto more = roots;
        more.push_back({4, 0, 0});
        expectProblem(problemsWith(s, more), r40, "tile size 4, the main file's is 8");
    }
    {
        // The header's root is not the index's.
        ResidualHeader h = regionHeader(s.header, {4, 1, 0}, 2);
        expectProblem(withRegion(h, {4, 0, 0}), r40, "root (4,1,0) in its header, the index says (4,0,0)");
    }
    {
        // A root outside the set: its parent (4,2,2) at level 4 is in no file (the region
        // rooted at (3,1,1) is cut to its root level for this).
        const std::string r311 = regionFilePath(s.main, {3, 1, 1});
        fs::remove(r311);
        copyResidual(*reader, r311, regionHeader(s.header, {3, 1, 1}, 0));
        const std::string r5 = regionFilePath(s.main, {5, 4, 4});
        copyResidual(*reader, r5, regionHeader(s.header, {5, 4, 4}, 1));
        fs::remove(r40);
        copyResidual(*reader, r40, good);
        auto more = roots;
        more.push_back({4, 0, 0});
        more.push_back({5, 4, 4});
        expectProblem(problemsWith(s, more), r5, "root (5,4,4) lies outside the set: no file holds its parent tile (4,2,2)");
        // Held by a region nested deeper: (4,2,2) is a region of its own, rooted in (3,1,1).
        const std::string r422 = regionFilePath(s.main, {4, 2, 2});
        copyResidual(*reader, r422, regionHeader(s.header, {4, 2, 2}, 0));
        more.push_back({4, 2, 2});
        EXPECT_TRUE(problemsWith(s, more).empty());
        fs::remove(r311);
        copyResidual(*reader, r311, regionHeader(s.header, {3, 1, 1}, 3));
    }
    {
        // Two regions with one root.
        writeRegionIndex(s.index, makeRegionIndex(s.main, PyramidKind::Residual, roots));
        RegionIndex index = readRegionIndex(s.index);
        index.regions.push_back({"copy.dat", {3, 0, 0}});
        fs::copy_file(regionFilePath(s.main, {3, 0, 0}), s.dir.file("set/copy.dat"));
        writeRegionIndex(s.index, index);
        expectProblem(pyramidSetProblems(resolvePyramidSet(s.index)), s.dir.file("set/copy.dat"),
                      "root (3,0,0) is also the root of");
    }
    {
        // The main file must be rooted at (0,0,0).
        RegionIndex index;
        index.main = fs::path(regionFilePath(s.main, {3, 0, 0})).filename().string();
        writeRegionIndex(s.index, index);
        expectProblem(pyramidSetProblems(resolvePyramidSet(s.index)), regionFilePath(s.main, {3, 0, 0}),
                      "the main file of a set must be rooted at tile (0,0,0), not (3,0,0)");
        try {
            openPyramidSet(s.setDir);
            ADD_FAILURE() << "a region as main accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("must be rooted at tile (0,0,0)"), std::string::npos);
        }
    }
    {
        // The index's kind is the main file's.
        RegionIndex index;
        index.kind = PyramidKind::Ortho;
        index.main = "DEM.dat";
        writeRegionIndex(s.index, index);
        expectProblem(pyramidSetProblems(resolvePyramidSet(s.index)), s.main, "holds a residual pyramid; the set is ortho");
    }
}

// An ortho pyramid of levels 0..2 written tile by tile, and the same split into a main file of
// level 0 and four regions rooted at level 1: tiles from the set are the single file's.
TEST(RegionSet, OrthoSetServesTheSingleFilesTiles) {
    test::TempDir dir;
    OrthoHeader h;
    h.maxLevel = 2;
    h.tileSize = 4;
    h.channels = 3;
    const int pixels = h.tilePixels();
    const auto tileOf = [&](int l, int x, int y) {
        std::vector<uint8_t> p(static_cast<size_t>(pixels * pixels * 3));
        for (size_t k = 0; k < p.size(); ++k) {
            p[k] = static_cast<uint8_t>(k * 7 + static_cast<size_t>(l * 31 + x * 11 + y * 5));
        }
        return p;
    };
    const std::string single = dir.file("RGB1.dat");
    {
        OrthoFileWriter w(single, h);
        for (int l = 0; l <= 2; ++l) {
            for (int y = 0; y < (1 << l); ++y) {
                for (int x = 0; x < (1 << l); ++x) {
                    w.writeTile(l, x, y, tileOf(l, x, y));
                }
            }
        }
        w.commit();
    }
    fs::create_directories(dir.file("set"));
    const std::string main = dir.file("set/RGB.dat");
    const auto reader = OrthoFileReader::open(single);
    {
        OrthoHeader m = h;
        m.maxLevel = 0;
        OrthoFileWriter w(main, m);
        w.writeTileBytes(0, 0, 0, reader->readTileBytes(0, 0, 0));
        w.commit();
    }
    std::vector<RegionRoot> roots;
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 2; ++x) {
            OrthoHeader r = h;
            r.maxLevel = 1;
            r.rootLevel = 1;
            r.rootTx = x;
            r.rootTy = y;
            OrthoFileWriter w(regionFilePath(main, {1, x, y}), r);
            w.writeTileBytes(0, 0, 0, reader->readTileBytes(1, x, y));
            for (int k = 0; k < 4; ++k) {
                w.writeTileBytes(1, k % 2, k / 2, reader->readTileBytes(2, 2 * x + k % 2, 2 * y + k / 2));
            }
            w.commit();
            roots.push_back({1, x, y});
        }
    }
    writeRegionIndex(regionIndexPath(main), makeRegionIndex(main, PyramidKind::Ortho, roots));
    const auto set = openOrthoSet(dir.file("set"));
    EXPECT_EQ(set->maxLevel(), 2);
    for (int l = 0; l <= 2; ++l) {
        for (int y = 0; y < (1 << l); ++y) {
            for (int x = 0; x < (1 << l); ++x) {
                EXPECT_EQ(set->tile(l, x, y), reader->readTile(l, x, y)) << l << "," << x << "," << y;
            }
        }
    }
    EXPECT_THROW(openResidualSet(dir.file("set")), Error);
    const std::string pyramid = programPath("pyramid");
    auto r = run(pyramid + " tile " + shellQuoted(single) + " 2 3 1 -o " + shellQuoted(dir.file("a.u8")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = run(pyramid + " tile " + shellQuoted(main) + " 2 3 1 -o " + shellQuoted(dir.file("b.u8")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(test::readFile(dir.file("a.u8")), test::readFile(dir.file("b.u8")));
    r = run(pyramid + " check " + shellQuoted(dir.file("set")));
    EXPECT_EQ(r.exitCode, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("ortho set of 5 files"), std::string::npos) << r.out;
    // Regions whose tiles differ from the main file's: channels, border, DXT.
    const std::string r00 = regionFilePath(main, {1, 0, 0});
    const auto rewrite = [&](int channels, uint32_t flags) {
        OrthoHeader o = h;
        o.maxLevel = 0;
        o.rootLevel = 1;
        o.channels = channels;
        o.flags = flags;
        fs::remove(r00);
        OrthoFileWriter w(r00, o);
        w.writeTile(0, 0, 0, std::vector<uint8_t>(static_cast<size_t>(o.tilePixels() * o.tilePixels() * channels), 9));
        w.commit();
        return pyramidSetProblems(resolvePyramidSet(main));
    };
    expectProblem(rewrite(4, 0), r00, "4 channels, the main file's has 3");
    expectProblem(rewrite(3, OrthoHeader::kFlagNoBorder), r00, "border 0, the main file's is 2");
    expectProblem(rewrite(3, OrthoHeader::kFlagDxt), r00, "DXT tiles, the main file's are not DXT");
}

// Copies ortho tiles as copyResidual does: tile (l, x, y) of the new file is the single file's
// tile (rootLevel + l, from.tx 2^l + x, from.ty 2^l + y) (`from`: the header's root unless given).
void copyOrtho(const OrthoFileReader& single, const std::string& path, const OrthoHeader& h, RegionRoot from) {
    OrthoFileWriter w(path, h);
    for (int l = 0; l <= h.maxLevel; ++l) {
        for (int y = 0; y < (1 << l); ++y) {
            for (int x = 0; x < (1 << l); ++x) {
                w.writeTileBytes(l, x, y, single.readTileBytes(h.rootLevel + l, (from.tx << l) + x, (from.ty << l) + y));
            }
        }
    }
    w.commit();
}

// An ortho pyramid encoded from an image (levels 0..2) and split into a main file of level 0 and
// four regions of levels 1..2 verifies against the image as the single file does; a region
// holding another subtree's tiles fails.
TEST(RegionSet, OrthoSetVerifiesAgainstTheSource) {
    test::TempDir dir;
    const int W = 64;
    std::vector<uint16_t> px(static_cast<size_t>(W * W * 3));
    for (size_t k = 0; k < px.size(); ++k) {
        px[k] = static_cast<uint16_t>((k * 37 + k / 191) % 251);
    }
    test::writeImage(dir.file("in.png"), W, W, 3, px, false);
    OrthoEncodeOptions o;
    o.levels.tileSize = 16;
    o.levels.colourSpace = ColourSpace::Linear;
    o.writeDxt = o.writeResiduals = false;
    encodeOrtho(dir.file("in.png"), dir.file("out"), o);
    const std::string single = dir.file("out/RGB.dat");
    const auto reader = OrthoFileReader::open(single);
    fs::create_directories(dir.file("set"));
    const std::string main = dir.file("set/RGB.dat");
    OrthoHeader m = reader->header();
    m.maxLevel = 0;
    copyOrtho(*reader, main, m, {0, 0, 0});
    std::vector<RegionRoot> roots;
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 2; ++x) {
            OrthoHeader r = reader->header();
            r.maxLevel = 1;
            r.rootLevel = 1;
            r.rootTx = x;
            r.rootTy = y;
            copyOrtho(*reader, regionFilePath(main, {1, x, y}), r, {1, x, y});
            roots.push_back({1, x, y});
        }
    }
    writeRegionIndex(regionIndexPath(main), makeRegionIndex(main, PyramidKind::Ortho, roots));
    OrthoVerifyOptions vo;
    vo.colourSpace = ColourSpace::Linear;
    const OrthoVerifyReport one = verifyOrtho(single, dir.file("in.png"), vo);
    ASSERT_TRUE(one.ok);
    for (const std::string& path : {main, regionIndexPath(main), dir.file("set")}) {
        const OrthoVerifyReport many = verifyOrtho(path, dir.file("in.png"), vo);
        EXPECT_TRUE(many.ok) << path;
        nlohmann::json a = toJson(one), b = toJson(many);
        a.erase("file");
        b.erase("file");
        EXPECT_EQ(a, b) << path;
    }
    const auto cli = run(programPath("pyramid") + " verify " + shellQuoted(dir.file("set")) + " --source " +
                         shellQuoted(dir.file("in.png")) + " --colour-space linear");
    EXPECT_EQ(cli.exitCode, 0) << cli.err << cli.out;
    // Region (1,0,0) holding the tiles of (1,1,0): the set no longer matches its source.
    OrthoHeader r = reader->header();
    r.maxLevel = 1;
    r.rootLevel = 1;
    fs::remove(regionFilePath(main, {1, 0, 0}));
    copyOrtho(*reader, regionFilePath(main, {1, 0, 0}), r, {1, 1, 0});
    EXPECT_FALSE(verifyOrtho(main, dir.file("in.png"), vo).ok);
}

} // namespace
} // namespace pyramid
