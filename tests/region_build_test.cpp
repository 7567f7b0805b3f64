// One region at a time (--region LEVEL,TX,TY, with or without --parent): the region file holds
// the whole pyramid's tiles of that subtree, byte for byte, whether its root lies in the
// encoder's in-memory top levels or below them; a main file plus the regions built one by one
// rebuild the whole pyramid's elevations; `pyramid check` accepts the region file; wrong roots,
// parents of another build or of other heights and combinations with --part or --max-file-bytes are refused with one
// line naming the option or file, and nothing is written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "formats/error.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/residual_producer.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/region_tiles.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

// 257 x 257 samples in tiles of 32 from a root of 8: minLevel 2, maxLevel 5; the encoder holds
// levels 0..3 in memory and encodes the level-4 subtrees from footprints.
DemEncodeOptions smallDem() {
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 8;
    o.scale = 0.25;
    o.threads = 2;
    return o;
}

struct Fixture {
    TempDir dir;
    std::string input;
    std::string whole;
    Fixture() {
        const int w = 257;
        input = dir.file("in.tif");
        test::writeFloatRaster(input, w, w, test::syntheticHeights(w, w, 2000.0f));
        whole = dir.file("whole.dat");
        const DemReport r = encodeDem(input, whole, smallDem());
        EXPECT_EQ(r.header.maxLevel, 5);
        EXPECT_EQ(r.header.minLevel, 2);
    }
};

DemReport buildRegion(const Fixture& f, const RegionRoot& root, const std::string& output,
                      const std::string& parent = "") {
    DemEncodeOptions o = smallDem();
    o.region = RegionRequest{root, parent};
    return encodeDem(f.input, output, o);
}

// The region file at `path` is the valid region file of `root` holding the whole pyramid's tiles
// of that subtree, byte for byte.
void expectRegionOfWhole(const std::string& path, const std::string& whole, const RegionRoot& root) {
    const auto region = ResidualFileReader::open(path);
    const auto all = ResidualFileReader::open(whole);
    const ResidualHeader& h = region->header();
    const ResidualHeader& w = all->header();
    EXPECT_EQ(h.minLevel, 0);
    EXPECT_EQ(h.tileSize, w.tileSize);
    EXPECT_EQ(h.scale, w.scale);
    EXPECT_EQ(h.rootLevel, root.level);
    EXPECT_EQ(h.rootTx, root.tx);
    EXPECT_EQ(h.rootTy, root.ty);
    ASSERT_EQ(h.maxLevel, w.maxLevel - root.level);
    test::expectRegionTilesOfWhole(*region, *all, root, path);
}

// A main file of the whole pyramid's levels 0..last, written through the library.
void writeTopLevels(const std::string& whole, const std::string& path, int last) {
    const auto all = ResidualFileReader::open(whole);
    ResidualHeader h = all->header();
    h.maxLevel = last;
    ResidualFileWriter out(path, h);
    for (int l = 0; l <= last; ++l) {
        const int64_t side = h.tilesPerSide(l);
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                out.writeTileBytes(l, tx, ty, all->readTileBytes(l, tx, ty));
            }
        }
    }
    out.commit();
}

// Every elevation tile of every level from `main` and `regions`, as the whole file gives it.
void expectSameElevations(const std::string& whole, const std::string& main, const std::vector<std::string>& regions) {
    const ResidualHeader h = ResidualFileReader::open(whole)->header();
    ResidualProducerOptions ro;
    ro.delta = h.minLevel;
    const auto one = std::make_shared<ResidualProducer>(whole, std::vector<std::string>{}, ro);
    const auto set = std::make_shared<ResidualProducer>(main, regions, ro);
    ElevationProducer a(one, ElevationProducerOptions{}), b(set, ElevationProducerOptions{});
    for (int l = h.minLevel; l <= h.maxLevel; ++l) {
        const int side = 1 << (l - h.minLevel);
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                ASSERT_EQ(a.tile(l - h.minLevel, tx, ty)->zf, b.tile(l - h.minLevel, tx, ty)->zf)
                    << "tile " << l << "," << tx << "," << ty;
            }
        }
    }
}

TEST(RegionBuild, RegionsAboveAndBelowTheCutHoldTheWholePyramidsTiles) {
    Fixture f;
    for (const RegionRoot root : {RegionRoot{2, 0, 0}, RegionRoot{3, 1, 0}, RegionRoot{4, 2, 3}, RegionRoot{4, 0, 3},
                                  RegionRoot{5, 7, 6}, RegionRoot{5, 0, 0}}) {
        const std::string path = f.dir.file(fs::path(regionFilePath("DEM.dat", root)).string());
        const DemReport r = buildRegion(f, root, path);
        EXPECT_EQ(r.header.rootLevel, root.level);
        EXPECT_EQ(r.tiles, ResidualFileReader::open(path)->header().tileCount());
        expectRegionOfWhole(path, f.whole, root);
        // No sidecar or index beside a region file.
        EXPECT_FALSE(fs::exists(path + ".regions.json"));
    }
}

TEST(RegionBuild, RegionsFromAParentFileHoldTheWholePyramidsTiles) {
    Fixture f;
    // Below the cut: the root's parent is read from the main file (levels 0..3).
    writeTopLevels(f.whole, f.dir.file("top3.dat"), 3);
    std::vector<std::string> regions;
    for (int ty = 0; ty < 4; ++ty) {
        for (int tx = 0; tx < 4; ++tx) {
            const RegionRoot root{4, tx, ty};
            const std::string path = regionFilePath(f.dir.file("top3.dat"), root);
            buildRegion(f, root, path, f.dir.file("top3.dat"));
            expectRegionOfWhole(path, f.whole, root);
            regions.push_back(path);
        }
    }
    // The main file and the regions built one at a time are the whole pyramid.
    expectSameElevations(f.whole, f.dir.file("top3.dat"), regions);

    // At or above the cut, and at minLevel (whose parent is a level of one smaller tile).
    writeTopLevels(f.whole, f.dir.file("top2.dat"), 2);
    buildRegion(f, RegionRoot{2, 0, 0}, f.dir.file("a.dat"), f.dir.file("top2.dat"));
    expectRegionOfWhole(f.dir.file("a.dat"), f.whole, RegionRoot{2, 0, 0});
    buildRegion(f, RegionRoot{3, 1, 1}, f.dir.file("b.dat"), f.dir.file("top2.dat"));
    expectRegionOfWhole(f.dir.file("b.dat"), f.whole, RegionRoot{3, 1, 1});
    // A deeper parent serves too, and --scale auto takes its scale.
    DemEncodeOptions o = smallDem();
    o.autoScale = true;
    o.region = RegionRequest{RegionRoot{5, 3, 2}, f.whole};
    encodeDem(f.input, f.dir.file("c.dat"), o);
    expectRegionOfWhole(f.dir.file("c.dat"), f.whole, RegionRoot{5, 3, 2});
}

TEST(RegionBuild, ASetsMainFileAndRegionsBuiltOneByOneAreTheWholePyramid) {
    Fixture f;
    // The split's main file (from --max-file-bytes) and its regions rebuilt one at a time, with
    // the set's main file as the parent.
    // The smallest of a few limits whose cut leaves some region of the first level below the main
    // file whole (down to the finest level): there the region built alone is that very file.
    std::string set;
    ResidualHeader mh;
    for (const uint64_t cap : {8000, 16000, 32000, 64000}) {
        DemEncodeOptions o = smallDem();
        o.maxFileBytes = cap;
        set = f.dir.file("set" + std::to_string(cap));
        fs::create_directories(set);
        const DemReport split = encodeDem(f.input, set + "/DEM.dat", o);
        mh = ResidualFileReader::open(set + "/DEM.dat")->header();
        bool whole = false;
        for (const auto& [name, bytes] : split.files) {
            const ResidualHeader rh = ResidualFileReader::open(set + "/" + name)->header();
            whole = whole || (rh.rootLevel == mh.maxLevel + 1 && rh.maxLevel == 5 - rh.rootLevel);
        }
        if (whole) {
            break;
        }
    }
    ASSERT_LT(mh.maxLevel, 5);
    writeTopLevels(f.whole, f.dir.file("DEM.dat"), mh.maxLevel);
    EXPECT_EQ(test::readFile(f.dir.file("DEM.dat")), test::readFile(set + "/DEM.dat"));
    std::vector<std::string> regions;
    int same = 0;
    const int level = mh.maxLevel + 1, side = 1 << (level - mh.minLevel);
    for (int ty = 0; ty < side; ++ty) {
        for (int tx = 0; tx < side; ++tx) {
            const RegionRoot root{level, tx, ty};
            const std::string path = regionFilePath(f.dir.file("DEM.dat"), root);
            buildRegion(f, root, path, set + "/DEM.dat");
            expectRegionOfWhole(path, f.whole, root);
            regions.push_back(path);
            // Where the set's region of that root holds the whole subtree, it is the same file.
            const std::string inSet = regionFilePath(set + "/DEM.dat", root);
            if (ResidualFileReader::open(inSet)->header().maxLevel == 5 - level) {
                EXPECT_EQ(test::readFile(path), test::readFile(inSet)) << inSet;
                ++same;
            }
        }
    }
    EXPECT_GT(same, 0);
    expectSameElevations(f.whole, f.dir.file("DEM.dat"), regions);
}

TEST(RegionBuild, TheProgramWritesARegionFileThatPyramidCheckAccepts) {
    Fixture f;
    const std::string common = " -q " + f.input + " --tile-size 32 --root-tile-size 8 --scale 0.25";
    test::RunResult run = test::run(test::programPath("preprocessDem") + common + " -o " + f.dir.file("DEM-L4-1-2.dat") +
                                    " --region 4,1,2");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    expectRegionOfWhole(f.dir.file("DEM-L4-1-2.dat"), f.whole, RegionRoot{4, 1, 2});
    EXPECT_FALSE(fs::exists(f.dir.file("DEM-L4-1-2.dat.geo.json")));
    writeTopLevels(f.whole, f.dir.file("top.dat"), 3);
    run = test::run(test::programPath("preprocessDem") + common + " -o " + f.dir.file("p.dat") +
                    " --region 4,1,2 --parent " + f.dir.file("top.dat"));
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_EQ(test::readFile(f.dir.file("p.dat")), test::readFile(f.dir.file("DEM-L4-1-2.dat")));
    run = test::run(test::programPath("pyramid") + " check " + f.dir.file("DEM-L4-1-2.dat"));
    EXPECT_EQ(run.exitCode, 0) << run.err;
}

TEST(RegionBuild, WrongRegionsAndParentsAreRefusedAndWriteNothing) {
    Fixture f;
    writeTopLevels(f.whole, f.dir.file("top.dat"), 3);
    const auto refused = [&](const RegionRoot& root, const std::string& parent, const std::string& expected,
                             const std::function<void(DemEncodeOptions&)>& change = {}) {
        DemEncodeOptions o = smallDem();
        o.region = RegionRequest{root, parent};
        if (change) {
            change(o);
        }
        try {
            encodeDem(f.input, f.dir.file("out/R.dat"), o);
            ADD_FAILURE() << "accepted " << tileText(root) << " " << parent;
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(expected), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
        EXPECT_FALSE(fs::exists(f.dir.file("out/R.dat")));
    };
    fs::create_directories(f.dir.file("out"));
    refused(RegionRoot{4, 4, 0}, "", "region: tile (4,4,0) is outside the pyramid");
    refused(RegionRoot{6, 0, 0}, "", "region: tile (6,0,0) cannot root a region");
    refused(RegionRoot{1, 0, 0}, "", "region: tile (1,0,0) cannot root a region");
    refused(RegionRoot{0, 0, 0}, "", "cannot root a region");
    refused(RegionRoot{4, 0, 0}, "", "scale: auto", [](DemEncodeOptions& o) { o.autoScale = true; });
    refused(RegionRoot{4, 0, 0}, "", "region: writes one region file; --max-file-bytes",
            [](DemEncodeOptions& o) { o.maxFileBytes = 8000; });
    // Parents of another build: another scale, tile size, deeper pyramid, too shallow a main file.
    refused(RegionRoot{4, 0, 0}, f.dir.file("top.dat"),
            "parent: " + f.dir.file("top.dat") + " is not a pyramid of this build: scale 0.25, not 0.5",
            [](DemEncodeOptions& o) { o.scale = 0.5; });
    refused(RegionRoot{4, 0, 0}, f.dir.file("top.dat"), "tileSize 32 and minLevel 2, not 64 and 3",
            [](DemEncodeOptions& o) { o.tileSize = 64; });
    refused(RegionRoot{2, 0, 0}, f.dir.file("top.dat"), "it has levels down to 3, this build to 2",
            [](DemEncodeOptions& o) { o.maxLevel = 2; });
    refused(RegionRoot{5, 0, 0}, f.dir.file("top.dat"), "needs level 4");
    refused(RegionRoot{4, 0, 0}, f.dir.file("missing.dat"), "missing.dat");
    // A pyramid of the same shape and scale from other heights (these 1 m higher: beyond
    // scale/2 = 0.125), below the encoder's cut and at it.
    std::vector<float> higher = test::syntheticHeights(257, 257, 2000.0f);
    for (float& h : higher) {
        h += 1.0f;
    }
    test::writeFloatRaster(f.dir.file("higher.tif"), 257, 257, higher);
    encodeDem(f.dir.file("higher.tif"), f.dir.file("higher.dat"), smallDem());
    refused(RegionRoot{4, 1, 2}, f.dir.file("higher.dat"),
            "parent: " + f.dir.file("higher.dat") + " does not hold this input's heights at level 3: ");
    refused(RegionRoot{3, 1, 0}, f.dir.file("higher.dat"), "does not hold this input's heights at level 2: ");
    // The programs: one line naming the option, a non-zero exit, nothing written.
    DemEncodeOptions half = smallDem();
    half.scale = 0.5;
    encodeDem(f.input, f.dir.file("half.dat"), half);
    const std::string common =
        " -q " + f.input + " --tile-size 32 --root-tile-size 8 --scale 0.25 -o " + f.dir.file("out/R.dat");
    for (const auto& [arguments, expected] : std::vector<std::pair<std::string, std::string>>{
             {" --region 4,1", "--region: must be LEVEL,TX,TY"},
             {" --region 9,0,0", "--region: tile (9,0,0) cannot root a region"},
             {" --region 4,0,0 --part 0/2", "--part"},
             {" --region 4,0,0 --max-file-bytes 8000", "--region: writes one region file"},
             {" --parent " + f.dir.file("top.dat"), "--parent"},
             {" --region 4,0,0 --parent " + f.dir.file("half.dat"),
              "--parent: " + f.dir.file("half.dat") + " is not a pyramid of this build: scale 0.5, not 0.25"}}) {
        const test::RunResult run = test::run(test::programPath("preprocessDem") + common + arguments);
        EXPECT_NE(run.exitCode, 0) << arguments;
        EXPECT_NE(run.err.find(expected), std::string::npos) << arguments << ": " << run.err;
        EXPECT_FALSE(fs::exists(f.dir.file("out/R.dat"))) << arguments;
    }
}

TEST(RegionBuild, ASphericalFacesRegionHoldsTheFacesTiles) {
    TempDir dir;
    const int W = 360, H = 180;
    std::vector<float> v(static_cast<size_t>(W) * H);
    for (int j = 0; j < H; ++j) {
        for (int i = 0; i < W; ++i) {
            v[static_cast<size_t>(i + j * W)] =
                static_cast<float>(1000.0 * std::sin(i * 0.05) * std::cos(j * 0.07) + 5.0 * i);
        }
    }
    test::writeFloatRaster(dir.file("map.tif"), W, H, v);
    SphericalDemOptions o;
    o.dem.tileSize = 8;
    o.dem.rootTileSize = 4;
    o.dem.maxLevel = 5;
    o.dem.scale = 0.25;
    o.faces = {3};
    encodeSphericalDem(dir.file("map.tif"), dir.file("whole"), o);
    for (const RegionRoot root : {RegionRoot{2, 1, 1}, RegionRoot{5, 9, 14}}) {
        SphericalDemOptions r = o;
        r.dem.region = RegionRequest{root, ""};
        encodeSphericalDem(dir.file("map.tif"), dir.file("region"), r);
        const std::string path = regionFilePath(dir.file("region/DEM3.dat"), root);
        ASSERT_TRUE(fs::exists(path)) << path;
        expectRegionOfWhole(path, dir.file("whole/DEM3.dat"), root);
        r.dem.region = RegionRequest{root, dir.file("whole/DEM3.dat")};
        encodeSphericalDem(dir.file("map.tif"), dir.file("parent"), r);
        expectRegionOfWhole(regionFilePath(dir.file("parent/DEM3.dat"), root), dir.file("whole/DEM3.dat"), root);
    }
    SphericalDemOptions two = o;
    two.faces = {3, 4};
    two.dem.region = RegionRequest{RegionRoot{2, 1, 1}, ""};
    EXPECT_THROW(encodeSphericalDem(dir.file("map.tif"), dir.file("two"), two), OptionError);
    EXPECT_FALSE(fs::exists(dir.file("two")));
}

} // namespace
} // namespace pyramid
