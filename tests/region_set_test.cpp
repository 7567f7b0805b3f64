// Region sets (doc/format.md 1.5) through the runtime: a DEM encoded as one file and split into a
// main file and region files, one of them nested in another (tests/support/region_sets.hpp), is
// found by its main file, index or directory, and reconstructs the single file bit for bit
// through the set producers, height queries and verification.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/runtime/height_query.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/region_sets.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::copyResidual;
using test::regionHeader;
using test::SplitDem;

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

} // namespace
} // namespace pyramid
