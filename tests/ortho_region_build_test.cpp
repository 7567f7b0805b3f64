// One ortho region at a time (preprocessOrtho / preprocessSphericalOrtho --region LEVEL,TX,TY,
// with or without --parent): each output's region file holds the whole pyramid's tiles of that
// subtree, byte for byte (the colour residuals against the enclosing pyramid's reconstruction),
// whether its root lies in the in-memory top levels or below them, and whichever walk reaches
// it; it is the very file a set written with --max-file-bytes holds for that root; wrong roots,
// parents of another build (by header, or by the colours they rebuild) and combinations with
// --part or --max-file-bytes are refused with one line naming the option or file, and nothing
// is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "libpyramid/api/encoders.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/region_tiles.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

const std::vector<std::string> kOutputs = {"RGB.dat", "dxt/RGB.dat", "residuals/RGB.dat"};

// 256 x 256 pixels in tiles of 8: levels 0..5. The walk with colour residuals holds levels 0..1
// in memory and encodes the level-2 subtrees from their footprints; the single pass (no
// residuals, or residuals against a parent) holds levels 0..2 and encodes level-3 subtrees.
OrthoEncodeOptions small() {
    OrthoEncodeOptions o;
    o.levels.tileSize = 8;
    o.levels.threads = 2;
    return o;
}

std::vector<uint8_t> bytesOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Fixture {
    TempDir dir;
    std::string input;
    Fixture() {
        const int w = 256;
        input = dir.file("in.png");
        test::writeImage(input, w, w, 3, test::texturedColours(w, w), false);
        const OrthoReport r = encodeOrtho(input, dir.file("whole"), small());
        EXPECT_EQ(r.maxLevel, 5);
    }
    std::string whole(const std::string& output) const { return dir.file("whole/" + output); }
};

// The region file at `path` is the valid region file of `root` holding the whole file's tiles
// of that subtree, byte for byte.
void expectRegionOfWhole(const std::string& path, const std::string& whole, const RegionRoot& root) {
    ASSERT_TRUE(fs::exists(path)) << path;
    const auto region = OrthoFileReader::open(path);
    const auto all = OrthoFileReader::open(whole);
    const OrthoHeader& h = region->header();
    const OrthoHeader& w = all->header();
    EXPECT_EQ(h.tileSize, w.tileSize);
    EXPECT_EQ(h.channels, w.channels);
    EXPECT_EQ(h.flags, w.flags);
    EXPECT_EQ(h.rootLevel, root.level);
    EXPECT_EQ(h.rootTx, root.tx);
    EXPECT_EQ(h.rootTy, root.ty);
    ASSERT_EQ(h.maxLevel, w.maxLevel - root.level);
    test::expectRegionTilesOfWhole(*region, *all, root, path);
}

OrthoReport buildRegion(const Fixture& f, const RegionRoot& root, const std::string& directory,
                        const std::string& parent = "",
                        const std::function<void(OrthoEncodeOptions&)>& change = {}) {
    OrthoEncodeOptions o = small();
    o.region = RegionRequest{root, parent};
    if (change) {
        change(o);
    }
    return encodeOrtho(f.input, directory, o);
}

TEST(OrthoRegionBuild, EveryOutputsRegionHoldsTheWholePyramidsTilesWithOrWithoutAParent) {
    Fixture f;
    // Roots in the in-memory top levels of both walks, between them, and below both.
    const std::vector<RegionRoot> roots = {{1, 1, 0}, {2, 3, 1}, {3, 5, 2}, {4, 9, 14}, {5, 31, 0}};
    int n = 0;
    for (const RegionRoot& root : roots) {
        for (const bool withParent : {false, true}) {
            const std::string dir = f.dir.file("r" + std::to_string(n++));
            const OrthoReport r = buildRegion(f, root, dir, withParent ? f.whole("residuals/RGB.dat") : "");
            ASSERT_TRUE(r.region.has_value());
            EXPECT_EQ(r.maxLevel, 5 - root.level);
            EXPECT_EQ(r.tiles, ((int64_t{1} << (2 * (6 - root.level))) - 1) / 3);
            ASSERT_EQ(r.levels.size(), static_cast<size_t>(6 - root.level));
            EXPECT_EQ(r.levels[0].tiles, 1);
            ASSERT_EQ(r.outputs.size(), kOutputs.size());
            for (const std::string& output : kOutputs) {
                const std::string path = regionFilePath(dir + "/" + output, root);
                EXPECT_EQ(r.outputs[&output - kOutputs.data()], path);
                expectRegionOfWhole(path, f.whole(output), root);
            }
            EXPECT_FALSE(fs::exists(dir + "/RGB.dat")) << "a region build writes no main file";
            EXPECT_FALSE(fs::exists(dir + "/RGB.dat.georef.json"));
        }
    }
}

TEST(OrthoRegionBuild, OutputsWithoutResidualsNeedNoLevelsAbove) {
    Fixture f;
    for (const RegionRoot root : {RegionRoot{1, 0, 1}, RegionRoot{3, 2, 7}, RegionRoot{5, 12, 20}}) {
        const std::string dir = f.dir.file("plain" + std::to_string(root.level));
        buildRegion(f, root, dir, "", [](OrthoEncodeOptions& o) { o.writeResiduals = false; });
        expectRegionOfWhole(regionFilePath(dir + "/RGB.dat", root), f.whole("RGB.dat"), root);
        expectRegionOfWhole(regionFilePath(dir + "/dxt/RGB.dat", root), f.whole("dxt/RGB.dat"), root);
        EXPECT_FALSE(fs::exists(dir + "/residuals"));
    }
}

// A region built alone is the file --max-file-bytes writes for that root, byte for byte.
TEST(OrthoRegionBuild, IsTheFileOfASetWithThatRoot) {
    Fixture f;
    OrthoEncodeOptions o = small();
    o.maxFileBytes = 16000;
    encodeOrtho(f.input, f.dir.file("set"), o);
    for (const std::string& output : kOutputs) {
        std::ifstream in(f.dir.file("set/" + output) + ".regions.json");
        const nlohmann::json index = nlohmann::json::parse(in);
        ASSERT_GE(index.at("regions").size(), 4u) << output;
        // The regions that hold their subtree down to the finest level (none nested below them):
        // the first and the last of the index.
        const auto rootOf = [](const nlohmann::json& entry) {
            const auto at = entry.at("root");
            return RegionRoot{at[0].get<int>(), at[1].get<int>(), at[2].get<int>()};
        };
        std::vector<nlohmann::json> leaves;
        for (const auto& entry : index.at("regions")) {
            const RegionRoot root = rootOf(entry);
            bool nests = false;
            for (const auto& other : index.at("regions")) {
                const RegionRoot r = rootOf(other);
                nests = nests || (r.level > root.level && regionHolds(root, r.level, r.tx, r.ty));
            }
            if (!nests) {
                leaves.push_back(entry);
            }
        }
        ASSERT_GE(leaves.size(), 2u) << output;
        for (const auto& entry : {leaves.front(), leaves.back()}) {
            const RegionRoot root = rootOf(entry);
            const std::string dir = f.dir.file("alone-" + tileText(root));
            buildRegion(f, root, dir, f.dir.file("set/residuals/RGB.dat"));
            const std::string name = entry.at("file").get<std::string>();
            const std::string sub = output.find('/') == std::string::npos ? "" : output.substr(0, output.find('/') + 1);
            const std::vector<uint8_t> alone = bytesOf(dir + "/" + sub + name);
            ASSERT_FALSE(alone.empty()) << dir + "/" + sub + name;
            EXPECT_EQ(alone, bytesOf(f.dir.file("set/" + sub + name))) << sub + name;
        }
    }
}

TEST(OrthoRegionBuild, ACubeFacesRegionHoldsTheFacesTiles) {
    TempDir dir;
    const int W = 256, H = 128;
    test::writeImage(dir.file("map.png"), W, H, 3, test::texturedColours(W, H), false);
    SphericalOrthoOptions o;
    o.ortho.levels.tileSize = 8;
    o.ortho.levels.maxLevel = 4;
    o.ortho.levels.threads = 2;
    o.faces = {2};
    encodeSphericalOrtho(dir.file("map.png"), dir.file("whole"), o);
    for (const RegionRoot root : {RegionRoot{1, 1, 0}, RegionRoot{4, 13, 6}}) {
        for (const bool withParent : {false, true}) {
            SphericalOrthoOptions r = o;
            r.ortho.region = RegionRequest{root, withParent ? dir.file("whole/residuals/RGB2.dat") : ""};
            const std::string out = dir.file(withParent ? "parent" : "region");
            const SphericalOrthoReport report = encodeSphericalOrtho(dir.file("map.png"), out, r);
            ASSERT_EQ(report.faces.size(), 1u);
            EXPECT_EQ(report.faces[0].ortho.tiles, ((int64_t{1} << (2 * (5 - root.level))) - 1) / 3);
            for (const std::string output : {"RGB2.dat", "dxt/RGB2.dat", "residuals/RGB2.dat"}) {
                expectRegionOfWhole(regionFilePath(out + "/" + output, root), dir.file("whole/" + output), root);
            }
        }
    }
    SphericalOrthoOptions two = o;
    two.faces = {2, 3};
    two.ortho.region = RegionRequest{RegionRoot{1, 0, 0}, ""};
    EXPECT_THROW(encodeSphericalOrtho(dir.file("map.png"), dir.file("two"), two), OptionError);
    EXPECT_FALSE(fs::exists(dir.file("two")));
}

TEST(OrthoRegionBuild, RefusesWhatCannotBeARegionOfThisBuild) {
    Fixture f;
    // Parents of other builds: tiles of another size, DXT tiles, elevations. (The TIFF file of the
    // same build has the residual file's header: its colours tell them apart, see below.)
    OrthoEncodeOptions other = small();
    other.levels.tileSize = 16;
    encodeOrtho(f.input, f.dir.file("other"), other);
    DemEncodeOptions dem;
    dem.tileSize = 16;
    dem.rootTileSize = 16;
    test::writeFloatRaster(f.dir.file("dem.tif"), 33, 33, test::syntheticHeights(33, 33, 100.0f));
    encodeDem(f.dir.file("dem.tif"), f.dir.file("dem.dat"), dem);
    const auto refused = [&](const RegionRoot& root, const std::string& parent, const std::string& expected,
                             const std::function<void(OrthoEncodeOptions&)>& change = {}) {
        try {
            buildRegion(f, root, f.dir.file("out"), parent, change);
            ADD_FAILURE() << "accepted " << tileText(root) << " " << parent;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
        }
        EXPECT_FALSE(fs::exists(f.dir.file("out"))) << expected;
    };
    refused(RegionRoot{0, 0, 0}, "", "region: tile (0,0,0) cannot root a region: its level must be from 1 to 5");
    refused(RegionRoot{6, 0, 0}, "", "region: tile (6,0,0) cannot root a region");
    refused(RegionRoot{3, 8, 0}, "", "region: tile (3,8,0) is outside the pyramid (level 3 has 8 tiles a side)");
    refused(RegionRoot{3, 0, 0}, "", "region: writes one region of each output; --max-file-bytes",
            [](OrthoEncodeOptions& o) { o.maxFileBytes = 100000; });
    refused(RegionRoot{3, 0, 0}, f.whole("residuals/RGB.dat"), "parent: gives the colour residuals' enclosing pyramid",
            [](OrthoEncodeOptions& o) { o.writeResiduals = false; });
    refused(RegionRoot{3, 0, 0}, f.dir.file("other/residuals/RGB.dat"),
            "is not the colour residuals of this build: tileSize 16 and 3 channels, not 8 and 3");
    refused(RegionRoot{3, 0, 0}, f.whole("dxt/RGB.dat"), "its tiles are DXT");
    refused(RegionRoot{3, 0, 0}, f.dir.file("dem.dat"), "it holds elevation residuals");
    refused(RegionRoot{3, 0, 0}, f.dir.file("missing.dat"), "missing.dat");

    // The program: one line naming the option, a non-zero exit, nothing written.
    const std::string common = " -q " + f.input + " --tile-size 8 -o " + f.dir.file("out");
    for (const auto& [arguments, expected] : std::vector<std::pair<std::string, std::string>>{
             {" --region 3,1", "--region: must be LEVEL,TX,TY"},
             {" --region 9,0,0", "--region: tile (9,0,0) cannot root a region"},
             {" --region 3,0,0 --part 0/2", "--part"},
             {" --parent " + f.whole("residuals/RGB.dat"), "--parent"},
             {" --region 3,0,0 --parent " + f.dir.file("other/residuals/RGB.dat"),
              "--parent: " + f.dir.file("other/residuals/RGB.dat") + " is not the colour residuals of this build"}}) {
        const test::RunResult run = test::run(test::programPath("preprocessOrtho") + common + arguments);
        EXPECT_NE(run.exitCode, 0) << arguments;
        EXPECT_NE(run.err.find(expected), std::string::npos) << arguments << ": " << run.err;
        EXPECT_FALSE(fs::exists(f.dir.file("out"))) << arguments;
    }
}

// A parent with this build's header that is not its colour residuals: the plain colours
// (RGB.dat has the very header of residuals/RGB.dat), or the residuals of another input. The
// rebuilt colours of the root's parent are not the input's, beyond the 1 the halved residuals
// allow: refused, naming the file and what to name instead. Level 0 of the plain colours is
// the residuals' (their root stores its colours): taken. JPEG residuals are checked by the
// parent's own quantisation tables: this input's are taken at any quality, another input's and
// the plain colours are refused.
TEST(OrthoRegionBuild, RefusesAParentThatDoesNotRebuildThisInputsColours) {
    Fixture f;
    std::vector<uint16_t> inverted = test::texturedColours(256, 256);
    for (uint16_t& v : inverted) {
        v = static_cast<uint16_t>(255 - v);
    }
    test::writeImage(f.dir.file("other.png"), 256, 256, 3, inverted, false);
    encodeOrtho(f.dir.file("other.png"), f.dir.file("other"), small());
    for (const RegionRoot& root : std::vector<RegionRoot>{{1, 1, 0}, {3, 5, 2}, {4, 9, 14}, {5, 31, 0}}) {
        for (const std::string& parent : {f.whole("RGB.dat"), f.dir.file("other/residuals/RGB.dat")}) {
            if (root.level == 1 && parent == f.whole("RGB.dat")) {
                continue; // level 0 of colour residuals is the colours: taken (below)
            }
            try {
                buildRegion(f, root, f.dir.file("out"), parent);
                ADD_FAILURE() << "accepted " << tileText(root) << " " << parent;
            } catch (const OptionError& e) {
                const std::string expected = "parent: " + parent + " does not rebuild this input's colours at level " +
                                             std::to_string(root.level - 1) + " (max error ";
                EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what();
                EXPECT_NE(std::string(e.what()).find("name the colour residuals of the same build, residuals/RGB.dat"),
                          std::string::npos)
                    << e.what();
            }
            EXPECT_FALSE(fs::exists(f.dir.file("out")));
        }
    }
    // The root's parent at level 0: the plain colours are what the residuals store there.
    buildRegion(f, RegionRoot{1, 1, 0}, f.dir.file("plain"), f.whole("RGB.dat"));
    expectRegionOfWhole(regionFilePath(f.dir.file("plain/residuals/RGB.dat"), {1, 1, 0}), f.whole("residuals/RGB.dat"),
                        {1, 1, 0});
    OrthoEncodeOptions jpeg = small();
    jpeg.residualCompression = TilePolicy::Jpeg;
    encodeOrtho(f.input, f.dir.file("jpeg"), jpeg);
    encodeOrtho(f.dir.file("other.png"), f.dir.file("other-jpeg"), jpeg);
    OrthoEncodeOptions coarse = jpeg;
    coarse.jpegQuality = 20;
    encodeOrtho(f.input, f.dir.file("jpeg20"), coarse);
    const auto jpegRegion = [](OrthoEncodeOptions& o) { o.residualCompression = TilePolicy::Jpeg; };
    for (const RegionRoot& root : std::vector<RegionRoot>{{1, 1, 0}, {3, 5, 2}, {4, 9, 14}, {5, 31, 0}}) {
        buildRegion(f, root, f.dir.file("j" + tileText(root)), f.dir.file("jpeg/residuals/RGB.dat"), jpegRegion);
        expectRegionOfWhole(regionFilePath(f.dir.file("j" + tileText(root) + "/residuals/RGB.dat"), root),
                            f.dir.file("jpeg/residuals/RGB.dat"), root);
        buildRegion(f, root, f.dir.file("q" + tileText(root)), f.dir.file("jpeg20/residuals/RGB.dat"), jpegRegion);
        EXPECT_TRUE(fs::exists(regionFilePath(f.dir.file("q" + tileText(root) + "/residuals/RGB.dat"), root)));
        for (const std::string& parent : {f.dir.file("other-jpeg/residuals/RGB.dat"), f.whole("RGB.dat")}) {
            if (root.level == 1) {
                // Level 0 (8 pixels of 32 x 32 averages) is about as grey in either input and in
                // the plain colours: within JPEG's loss, as it is taken.
                continue;
            }
            try {
                buildRegion(f, root, f.dir.file("out"), parent, jpegRegion);
                ADD_FAILURE() << "accepted " << tileText(root) << " " << parent;
            } catch (const OptionError& e) {
                const std::string expected = "parent: " + parent + " does not rebuild this input's colours at level " +
                                             std::to_string(root.level - 1) + " (";
                EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what();
                const bool jpegParent = parent != f.whole("RGB.dat");
                EXPECT_EQ(std::string(e.what()).find("in an 8 x 8 JPEG block, beyond the ") != std::string::npos,
                          jpegParent)
                    << e.what();
            }
            EXPECT_FALSE(fs::exists(f.dir.file("out")));
        }
    }

    // The program: one line, a non-zero exit, nothing written.
    const test::RunResult run =
        test::run(test::programPath("preprocessOrtho") + " -q " + f.input + " --tile-size 8 -o " + f.dir.file("out") +
                  " --region 4,9,14 --parent " + f.whole("RGB.dat"));
    EXPECT_NE(run.exitCode, 0);
    const std::string expected = "preprocessOrtho: --parent: " + f.whole("RGB.dat") + " does not rebuild";
    EXPECT_EQ(run.err.rfind(expected, 0), 0u) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_FALSE(fs::exists(f.dir.file("out")));
}

TEST(OrthoRegionBuild, TheProgramWritesTheRegionAndSaysWhichItIs) {
    Fixture f;
    const std::string out = f.dir.file("out");
    const test::RunResult run =
        test::run(test::programPath("preprocessOrtho") + " " + f.input + " --tile-size 8 -o " + out +
                  " --region 4,9,14 --parent " + f.whole("residuals/RGB.dat") + " --report " + f.dir.file("r.json"));
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_NE(run.err.find("the region rooted at tile (4,9,14): its levels 0..1"), std::string::npos) << run.err;
    std::ifstream in(f.dir.file("r.json"));
    const nlohmann::json report = nlohmann::json::parse(in);
    EXPECT_EQ(report.at("region"), nlohmann::json::array({4, 9, 14}));
    EXPECT_EQ(report.at("tiles"), 5);
    for (const std::string& output : kOutputs) {
        expectRegionOfWhole(regionFilePath(out + "/" + output, RegionRoot{4, 9, 14}), f.whole(output),
                            RegionRoot{4, 9, 14});
    }
    const test::RunResult check =
        test::run(test::programPath("pyramid") + " check " + out + "/residuals/RGB-L4-9-14.dat");
    EXPECT_EQ(check.exitCode, 0) << check.out << check.err;
}

} // namespace
} // namespace pyramid
