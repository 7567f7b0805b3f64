// Region set names and indexes (doc/format.md 1.5, formats/pyramid_set.hpp): a region file's name
// parses back to its main file and root, and no other name does; the index round-trips and
// refuses text that is not one, with its message.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"

namespace pyramid {
namespace {

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

} // namespace
} // namespace pyramid
