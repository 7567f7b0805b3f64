// The rules of a region set (doc/format.md 1.5, pyramidSetProblems): every rule rejects a split
// DEM (tests/support/region_sets.hpp) that breaks it, naming the file and what breaks.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "tests/support/region_sets.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::copyResidual;
using test::expectProblem;
using test::regionHeader;
using test::SplitDem;

// Rewrites the set's index with `roots` (files named after them) and returns the set's problems.
std::vector<std::string> problemsWith(const SplitDem& s, const std::vector<RegionRoot>& roots) {
    writeRegionIndex(s.index, makeRegionIndex(s.main, PyramidKind::Residual, roots));
    return pyramidSetProblems(resolvePyramidSet(s.index));
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

} // namespace
} // namespace pyramid
