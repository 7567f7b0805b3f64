// Builds split into parts (--part I/N and `pyramid merge`, the ranks of an MPI run): the merged
// files are the single run's, byte for byte, for any number of parts, planar and spherical, one
// file or a region set; a merge refuses parts that are missing, doubled or of another build, and
// writes nothing then; an int16 overflow in one part's subtrees fails that part with the scale to
// use. The same under mpirun: split_build_mpi_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "libpyramid/api/encoders.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

DemEncodeOptions smallDem() {
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 8;
    o.scale = 0.25;
    o.threads = 2;
    return o;
}

// Runs the build as `count` parts into dir/parts and merges them into dir/merged.
std::vector<std::string> buildInParts(const std::string& input, const std::string& partsDir, int count,
                                      const DemEncodeOptions& options) {
    fs::create_directories(partsDir);
    std::vector<std::string> parts;
    for (int i = 0; i < count; ++i) {
        parts.push_back(runPart(i, count, partsDir + "/DEM.dat", kResidualPartFormat, {{"test", 1}}, [&](const PartContext& part) {
            const ResidualShare share{part.index, part.count, part.out, part.agree};
            DemEncodeOptions o = options;
            o.share = &share;
            o.threads = 1 + i % 2;
            encodeDem(input, partsDir + "/DEM.dat", o);
        }));
    }
    return parts;
}

TEST(SplitBuild, PartsMergeIntoTheSingleRunsBytesForAnyCount) {
    TempDir dir;
    const int w = 257;
    test::writeFloatRaster(dir.file("in.tif"), w, w, test::syntheticHeights(w, w, 2000.0f));
    const DemEncodeOptions o = smallDem();
    fs::create_directories(dir.file("one"));
    const DemReport single = encodeDem(dir.file("in.tif"), dir.file("one/DEM.dat"), o);
    for (const int count : {1, 2, 3, 4, 5, 7}) { // 4 groups of 4 subtrees: 5 and 7 leave parts empty
        const std::string parts = dir.file("p" + std::to_string(count));
        const std::vector<std::string> files = buildInParts(dir.file("in.tif"), parts, count, o);
        std::vector<std::string> shuffled(files.rbegin(), files.rend());
        const ResidualMergeReport merged = mergeResidualParts(shuffled, dir.file("m" + std::to_string(count)));
        EXPECT_EQ(test::readFile(dir.file("m" + std::to_string(count) + "/DEM.dat")), test::readFile(dir.file("one/DEM.dat")))
            << count << " parts";
        ASSERT_EQ(merged.pyramids.size(), 1u);
        const ResidualPyramidReport& p = merged.pyramids[0];
        EXPECT_EQ(p.tiles, single.tiles);
        EXPECT_EQ(p.sharedTiles, single.sharedTiles);
        EXPECT_EQ(p.bytes, single.bytes);
        ASSERT_EQ(p.levels.size(), single.levels.size());
        for (size_t l = 0; l < p.levels.size(); ++l) {
            EXPECT_EQ(p.levels[l].samples, single.levels[l].samples);
            EXPECT_EQ(p.levels[l].maxError, single.levels[l].maxError);
            EXPECT_EQ(p.levels[l].rmsError, single.levels[l].rmsError); // summed in the same order
        }
    }
}

TEST(SplitBuild, PartsMergeIntoTheSameRegionSet) {
    TempDir dir;
    const int w = 257;
    test::writeFloatRaster(dir.file("in.tif"), w, w, test::syntheticHeights(w, w, 2000.0f));
    DemEncodeOptions o = smallDem();
    o.maxFileBytes = 8000;
    fs::create_directories(dir.file("one"));
    encodeDem(dir.file("in.tif"), dir.file("one/DEM.dat"), o);
    const auto single = test::filesUnder(dir.file("one"));
    ASSERT_GT(single.size(), 3u); // a set: main, regions, index
    const std::vector<std::string> files = buildInParts(dir.file("in.tif"), dir.file("parts"), 3, o);
    mergeResidualParts(files, dir.file("merged"));
    EXPECT_TRUE(test::filesUnder(dir.file("merged")) == single);
}

TEST(SplitBuild, SphericalPartsMergeIntoTheSixFaces) {
    TempDir dir;
    const int W = 360, H = 180;
    std::vector<float> v(static_cast<size_t>(W) * H);
    for (int j = 0; j < H; ++j) {
        for (int i = 0; i < W; ++i) {
            v[static_cast<size_t>(i + j * W)] = static_cast<float>(1000.0 * std::sin(i * 0.05) * std::cos(j * 0.07) + 5.0 * i);
        }
    }
    test::writeFloatRaster(dir.file("map.tif"), W, H, v);
    SphericalDemOptions o;
    o.dem.tileSize = 8;
    o.dem.rootTileSize = 4;
    o.dem.maxLevel = 4;
    o.dem.scale = 0.25;
    encodeSphericalDem(dir.file("map.tif"), dir.file("one"), o);
    const auto single = test::filesUnder(dir.file("one"));
    ASSERT_EQ(single.size(), 6u);
    for (const int count : {2, 3, 8}) {
        const std::string parts = dir.file("p" + std::to_string(count));
        fs::create_directories(parts);
        std::vector<std::string> files;
        for (int i = 0; i < count; ++i) {
            files.push_back(runPart(i, count, parts + "/DEM", kResidualPartFormat, {{"test", 2}}, [&](const PartContext& part) {
            const ResidualShare share{part.index, part.count, part.out, part.agree};
                SphericalDemOptions run = o;
                run.dem.share = &share;
                encodeSphericalDem(dir.file("map.tif"), parts, run);
            }));
        }
        const std::string merged = dir.file("m" + std::to_string(count));
        const ResidualMergeReport report = mergeResidualParts(files, merged);
        EXPECT_EQ(report.pyramids.size(), 6u);
        EXPECT_TRUE(test::filesUnder(merged) == single) << count << " parts";
    }
}

TEST(SplitBuild, SparsePlanetPartsMergeIntoTheSingleRunsSets) {
    TempDir dir;
    // 2 x 2 degrees near Mount Rainier on a planet at level 11: each face a sparse set.
    const int W = 64;
    std::vector<float> v(static_cast<size_t>(W * W));
    for (int j = 0; j < W; ++j) {
        for (int i = 0; i < W; ++i) {
            v[static_cast<size_t>(i + j * W)] = 1000.0f + 37.0f * static_cast<float>(i) - 21.0f * static_cast<float>(j);
        }
    }
    test::writeGeoTiff(dir.file("map.tif"), W, W, v, test::geographicTags(4326, -122.5, 47.5, 2.0 / W));
    SphericalDemOptions o;
    o.dem.tileSize = 32;
    o.dem.rootTileSize = 4;
    o.dem.maxLevel = 11;
    o.dem.scale = 0.25;
    encodeSphericalDem(dir.file("map.tif"), dir.file("one"), o);
    const auto single = test::filesUnder(dir.file("one"));
    ASSERT_GT(single.size(), 12u); // six sets, face 1 with regions
    for (const int count : {2, 3}) {
        const std::string parts = dir.file("p" + std::to_string(count));
        fs::create_directories(parts);
        std::vector<std::string> files;
        for (int i = 0; i < count; ++i) {
            files.push_back(runPart(i, count, parts + "/DEM", kResidualPartFormat, {{"test", 3}}, [&](const PartContext& part) {
                const ResidualShare share{part.index, part.count, part.out, part.agree};
                SphericalDemOptions run = o;
                run.dem.share = &share;
                run.dem.threads = 1 + i % 2;
                encodeSphericalDem(dir.file("map.tif"), parts, run);
            }));
        }
        const std::string merged = dir.file("m" + std::to_string(count));
        mergeResidualParts(files, merged);
        EXPECT_TRUE(test::filesUnder(merged) == single) << count << " parts";
    }
}

TEST(SplitBuild, MergeRefusesIncompleteDoubledOrForeignPartsAndWritesNothing) {
    TempDir dir;
    const int w = 129;
    test::writeFloatRaster(dir.file("in.tif"), w, w, test::syntheticHeights(w, w, 500.0f));
    DemEncodeOptions o = smallDem();
    const std::vector<std::string> files = buildInParts(dir.file("in.tif"), dir.file("a"), 3, o);
    const auto expectRefused = [&](const std::vector<std::string>& parts, const std::string& words) {
        try {
            mergeResidualParts(parts, dir.file("out"));
            ADD_FAILURE() << "merged: " << words;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
        EXPECT_FALSE(fs::exists(dir.file("out/DEM.dat")));
    };
    expectRefused({files[0], files[2]}, "part 1 of 3 is missing");
    expectRefused({files[0], files[1], files[1], files[2]}, "is given twice");
    o.scale = 0.5; // another build of the same input
    fs::create_directories(dir.file("b"));
    const std::string other = runPart(1, 3, dir.file("b/DEM.dat"), kResidualPartFormat, {{"test", 3}}, [&](const PartContext& part) {
            const ResidualShare share{part.index, part.count, part.out, part.agree};
        DemEncodeOptions run = o;
        run.share = &share;
        encodeDem(dir.file("in.tif"), dir.file("b/DEM.dat"), run);
    });
    expectRefused({files[0], other, files[2]}, "is a part of another build");
    test::writeFloatRaster(dir.file("not.tif"), 4, 4, std::vector<float>(16, 1.0f));
    expectRefused({files[0], dir.file("not.tif"), files[2]}, "not a part file");
    // A part cut short.
    const std::string bytes = test::readFile(files[1]);
    std::ofstream(dir.file("short.part"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    expectRefused({files[0], dir.file("short.part"), files[2]}, "incomplete part file");
}

TEST(SplitBuild, AnOverflowInOnePartsSubtreesFailsThatPartWithTheScaleToUse) {
    TempDir dir;
    const int w = 257;
    test::writeFloatRaster(dir.file("in.tif"), w, w, test::overflowSpikes(w));
    DemEncodeOptions o = smallDem();
    o.autoScale = true;
    fs::create_directories(dir.file("one"));
    const DemReport single = encodeDem(dir.file("in.tif"), dir.file("one/DEM.dat"), o);
    ASSERT_GT(single.scalesTried.size(), 1u); // the single run raised its scale
    fs::create_directories(dir.file("p"));
    for (const int index : {0, 1}) { // their subtrees are all 0
        runPart(index, 3, dir.file("p/DEM.dat"), kResidualPartFormat, {{"test", 4}}, [&](const PartContext& part) {
            const ResidualShare share{part.index, part.count, part.out, part.agree};
            DemEncodeOptions run = o;
            run.share = &share;
            encodeDem(dir.file("in.tif"), dir.file("p/DEM.dat"), run);
        });
        fs::remove(partFileName(dir.file("p/DEM.dat"), index, 3));
    }
    try {
        runPart(2, 3, dir.file("p/DEM.dat"), kResidualPartFormat, {{"test", 4}}, [&](const PartContext& part) {
            const ResidualShare share{part.index, part.count, part.out, part.agree};
            DemEncodeOptions run = o;
            run.share = &share;
            encodeDem(dir.file("in.tif"), dir.file("p/DEM.dat"), run);
        });
        ADD_FAILURE() << "the last part did not fail";
    } catch (const OptionError& e) {
        EXPECT_NE(e.problem().find("run every part again with --scale"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_empty(dir.file("p")));
}

TEST(SplitBuildCli, PartsOfTheProgramsMergeIntoTheSingleRunsFilesSidecarIncluded) {
    const std::string input = test::sharedFixturePath("inputs/mt_rainier_90m.tif");
    ASSERT_FALSE(input.empty()) << "../shared/fixtures is needed";
    TempDir dir;
    const std::string dem = test::programPath("preprocessDem") + " " + input + " -q -o ";
    ASSERT_EQ(test::run(dem + dir.file("one/DEM.dat")).exitCode, 0);
    ASSERT_TRUE(fs::exists(dir.file("one/DEM.dat.georef.json")));
    for (int i = 0; i < 3; ++i) {
        // Options that do not change the files may differ from part to part.
        const test::RunResult r = test::run(dem + dir.file("p/DEM.dat") + " --part " + std::to_string(i) + "/3 --threads " +
                                            std::to_string(1 + i % 2) + (i == 1 ? " --progress none" : ""));
        ASSERT_EQ(r.exitCode, 0) << r.err;
    }
    EXPECT_FALSE(fs::exists(dir.file("p/DEM.dat")));
    // A part of another build (another scale) is refused by name, and nothing is written.
    ASSERT_EQ(test::run(dem + dir.file("q/DEM.dat") + " --part 1/3 --scale 2").exitCode, 0);
    const std::string merge = test::programPath("pyramid") + " merge -q ";
    const test::RunResult foreign = test::run(merge + dir.file("p/DEM.dat.part-0-of-3 ") + dir.file("q/DEM.dat.part-1-of-3 ") +
                                              dir.file("p/DEM.dat.part-2-of-3"));
    EXPECT_EQ(foreign.exitCode, 1);
    EXPECT_NE(foreign.err.find("q/DEM.dat.part-1-of-3: is a part of another build"), std::string::npos) << foreign.err;
    EXPECT_FALSE(fs::exists(dir.file("p/DEM.dat")));
    // Into another directory, keeping the parts: they merge again below.
    const test::RunResult kept =
        test::run(merge + "--keep-parts -o " + dir.file("elsewhere") + " " + dir.file("p/DEM.dat.part-*-of-3"));
    ASSERT_EQ(kept.exitCode, 0) << kept.err;
    EXPECT_TRUE(test::filesUnder(dir.file("elsewhere")) == test::filesUnder(dir.file("one")));
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(fs::exists(dir.file("p/DEM.dat.part-" + std::to_string(i) + "-of-3"))) << "kept";
    }
    EXPECT_FALSE(fs::exists(dir.file("p/DEM.dat")));
    const test::RunResult r = test::run(merge + dir.file("p/DEM.dat.part-*-of-3"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(test::filesUnder(dir.file("p")) == test::filesUnder(dir.file("one"))); // the parts are gone
    const test::RunResult bad = test::run(dem + dir.file("p/DEM.dat") + " --part 3/3");
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("--part: must be I/N with 0 <= I < N, not 3/3"), std::string::npos) << bad.err;
}

TEST(SplitBuildCli, MaxFileBytesWithoutASizeWritesTheFileAndAnIndex) {
    const std::string input = test::sharedFixturePath("inputs/mt_rainier_90m.tif");
    ASSERT_FALSE(input.empty()) << "../shared/fixtures is needed";
    TempDir dir;
    const test::RunResult r = test::run(test::programPath("preprocessDem") + " " + input + " -q --max-file-bytes -o " +
                                        dir.file("DEM.dat"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir.file("DEM.dat.regions.json")));
}

// An ortho build in parts, both walk orders (with colour residuals: top levels first; without:
// subtrees first, the top levels from bands in the last share), planar and on the cube.
// One test per program, so that the two run side by side.
class SplitBuildOrtho : public ::testing::TestWithParam<std::string> {};

TEST_P(SplitBuildOrtho, PartsMergeIntoTheSingleRunsOutputs) {
    TempDir dir;
    const std::string image = test::samplePath("bluemarble.png");
    const std::string program = GetParam();
    for (const std::string outputs : {"tiff,dxt,residuals", "tiff,dxt"}) {
        const std::string tag = program + "-" + outputs;
        const std::string cmd = test::programPath(program) + " " + image + " --outputs " + outputs +
                                (program == "preprocessOrtho" ? " --tile-size 64" : " --tile-size 16 --max-level 3 --faces 1,5") +
                                " --max-file-bytes 40K -q -o ";
        ASSERT_EQ(test::run(cmd + dir.file("one-" + tag)).exitCode, 0);
        // Without residuals, one part count (the full outputs take two).
        for (const int count : outputs == "tiff,dxt" ? std::vector<int>{3} : std::vector<int>{2, 5}) {
            const std::string parts = dir.file("p" + std::to_string(count) + "-" + tag);
            for (int i = 0; i < count; ++i) {
                const test::RunResult r =
                    test::run(cmd + parts + " --part " + std::to_string(i) + "/" + std::to_string(count));
                ASSERT_EQ(r.exitCode, 0) << r.err;
            }
            const test::RunResult m = test::run(test::programPath("pyramid") + " merge -q " + parts + "/RGB.part-*");
            ASSERT_EQ(m.exitCode, 0) << m.err;
            EXPECT_TRUE(test::filesUnder(parts) == test::filesUnder(dir.file("one-" + tag))) << tag << ", " << count << " parts";
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Programs, SplitBuildOrtho, ::testing::Values("preprocessOrtho", "preprocessSphericalOrtho"));

TEST(SplitBuild, AnOrthoPartIsNoResidualPart) {
    TempDir dir;
    const std::string image = test::samplePath("bluemarble.png");
    ASSERT_EQ(test::run(test::programPath("preprocessOrtho") + " " + image + " --tile-size 64 -q --part 0/2 -o " +
                        dir.file("mixed")).exitCode, 0);
    TempDir dem;
    test::writeFloatRaster(dem.file("in.tif"), 129, 129, test::syntheticHeights(129, 129, 500.0f));
    const std::vector<std::string> residual = buildInParts(dem.file("in.tif"), dem.file("p"), 2, smallDem());
    try {
        mergeResidualParts({residual[0], dir.file("mixed/RGB.part-0-of-2")}, dem.file("out"));
        ADD_FAILURE() << "merged an ortho part into a residual build";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is a libpyramid ortho part, not a libpyramid residual part"), std::string::npos)
            << e.what();
    }
}

} // namespace
} // namespace pyramid
