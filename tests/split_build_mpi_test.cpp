// Builds split over the ranks of an MPI run (when the programs are built with MPI): 1, 2 and 3
// ranks give the single run's bytes, planar and spherical, DEM and ortho; an automatic scale
// raised by one rank's overflow is raised on every rank; a failing rank fails the run with its
// message and leaves nothing; and the MPI module, which holds Open MPI, is loaded under mpirun
// only.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

std::string mpirun(int ranks) {
    return std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 ") +
           PYRAMID_TEST_MPIRUN + " -n " + std::to_string(ranks) + " --oversubscribe ";
}

TEST(SplitBuildMpi, RanksWriteTheSingleRunsBytes) {
    TempDir dir;
    const int w = 257;
    test::writeFloatRaster(dir.file("in.tif"), w, w, test::syntheticHeights(w, w, 2000.0f));
    const std::string dem = test::programPath("preprocessDem") + " " + dir.file("in.tif") +
                            " --tile-size 32 --root-tile-size 8 --scale 0.25 --threads 1 -q -o ";
    ASSERT_EQ(test::run(dem + dir.file("one/DEM.dat")).exitCode, 0);
    const std::string sphere = test::programPath("preprocessSphericalDem") + " " + dir.file("in.tif") +
                               " --tile-size 8 --root-tile-size 4 --max-level 4 --scale 0.25 --threads 1 -q -o ";
    ASSERT_EQ(test::run(sphere + dir.file("sphere")).exitCode, 0);
    for (const int ranks : {1, 2, 3}) {
        const std::string n = std::to_string(ranks);
        const test::RunResult r = test::run(mpirun(ranks) + dem + dir.file("dem" + n + "/DEM.dat"));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_TRUE(test::filesUnder(dir.file("dem" + n)) == test::filesUnder(dir.file("one"))) << ranks << " ranks";
        const test::RunResult s = test::run(mpirun(ranks) + sphere + dir.file("sphere" + n) + " --max-file-bytes 3K");
        ASSERT_EQ(s.exitCode, 0) << s.err;
        const test::RunResult t = test::run(sphere + dir.file("sphere-one" + n) + " --max-file-bytes 3K");
        ASSERT_EQ(t.exitCode, 0) << t.err;
        EXPECT_TRUE(test::filesUnder(dir.file("sphere" + n)) == test::filesUnder(dir.file("sphere-one" + n))) << ranks << " ranks";
        EXPECT_GT(test::filesUnder(dir.file("sphere" + n)).size(), 12u); // sets: faces split into regions
    }
}

TEST(SplitBuildMpi, OrthoRanksWriteTheSingleRunsOutputs) {
    TempDir dir;
    const std::string image = test::samplePath("bluemarble.png");
    for (const std::string outputs : {"tiff,dxt,residuals", "tiff"}) {
        const std::string planar = test::programPath("preprocessOrtho") + " " + image + " --outputs " + outputs +
                                   " --tile-size 64 --threads 1 -q -o ";
        const std::string sphere = test::programPath("preprocessSphericalOrtho") + " " + image + " --outputs " + outputs +
                                   " --tile-size 16 --max-level 3 --threads 1 -q -o ";
        ASSERT_EQ(test::run(planar + dir.file("one")).exitCode, 0);
        ASSERT_EQ(test::run(sphere + dir.file("sphere")).exitCode, 0);
        for (const int ranks : {2, 3}) {
            const std::string n = std::to_string(ranks) + outputs;
            const test::RunResult r = test::run(mpirun(ranks) + planar + dir.file("o" + n));
            ASSERT_EQ(r.exitCode, 0) << r.err;
            EXPECT_TRUE(test::filesUnder(dir.file("o" + n)) == test::filesUnder(dir.file("one"))) << ranks << " ranks, " << outputs;
            const test::RunResult s = test::run(mpirun(ranks) + sphere + dir.file("s" + n));
            ASSERT_EQ(s.exitCode, 0) << s.err;
            EXPECT_TRUE(test::filesUnder(dir.file("s" + n)) == test::filesUnder(dir.file("sphere"))) << ranks << " ranks, " << outputs;
        }
        fs::remove_all(dir.file("one"));
        fs::remove_all(dir.file("sphere"));
    }
}

TEST(SplitBuildMpi, AnAutomaticScaleRaisedByOneRankIsRaisedOnEveryRank) {
    TempDir dir;
    const int w = 257;
    test::writeFloatRaster(dir.file("in.tif"), w, w, test::overflowSpikes(w));
    const std::string dem = test::programPath("preprocessDem") + " " + dir.file("in.tif") +
                            " --tile-size 32 --root-tile-size 8 --scale auto --threads 1 -q -o ";
    ASSERT_EQ(test::run(dem + dir.file("one/DEM.dat")).exitCode, 0);
    const test::RunResult r = test::run(mpirun(3) + dem + dir.file("three/DEM.dat"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(test::readFile(dir.file("three/DEM.dat")), test::readFile(dir.file("one/DEM.dat")));
}

TEST(SplitBuildMpi, AFailingRankFailsTheRunWithItsMessageAndLeavesNothing) {
    TempDir dir;
    const int w = 257;
    std::vector<float> v = test::syntheticHeights(w, w, 2000.0f);
    // An infinite height at an odd sample near the far corner: only the last subtrees read it.
    v[static_cast<size_t>((w - 4) + 3 * w)] = INFINITY; // north-east: the last subtree's (rank 2)
    test::writeFloatRaster(dir.file("in.tif"), w, w, v);
    fs::create_directories(dir.file("out"));
    test::writeFloatRaster(dir.file("out/keep.tif"), 2, 2, std::vector<float>(4, 1.0f));
    const auto before = test::filesUnder(dir.file("out"));
    const test::RunResult r = test::run(mpirun(3) + test::programPath("preprocessDem") + " " + dir.file("in.tif") +
                                        " --tile-size 32 --root-tile-size 8 --threads 1 -q -o " + dir.file("out/DEM.dat"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.err.find("preprocessDem: rank 2: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("in.tif"), std::string::npos) << r.err;
    EXPECT_TRUE(test::filesUnder(dir.file("out")) == before); // no part, no staging directory, no output
}

// Under mpirun a program that cannot load the MPI module stops at once, in one line, and writes
// nothing: run alone it would write the whole build beside the other ranks. The launcher's
// environment is given by hand; the module is named where there is none.
TEST(SplitBuildMpi, ARankWithoutTheMpiModuleStopsAndWritesNothing) {
    TempDir dir;
    const std::string missing = dir.file("missing.so");
    const test::RunResult r = test::run("OMPI_COMM_WORLD_SIZE=2 PYRAMID_MPI_MODULE=" + test::shellQuoted(missing) + " " +
                                        test::programPath("preprocessDem") + " " + test::samplePath("dem.tif") +
                                        " -q -o " + dir.file("out/DEM.dat"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.err, "preprocessDem: started by mpirun, but the MPI module cannot be loaded (" + missing +
                         " not found; set PYRAMID_MPI_MODULE to its path)\n");
    EXPECT_FALSE(fs::exists(dir.file("out")));
}

// Open MPI is in the module only: a program started by hand never loads it.
TEST(SplitBuildMpi, TheProgramsDoNotLinkOpenMpi) {
    for (const std::string program : {"pyramid", "preprocessDem", "preprocessOrtho", "preprocessSphericalDem"}) {
        const test::RunResult r = test::run("ldd " + test::programPath(program));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_EQ(r.out.find("libmpi"), std::string::npos) << program << ":\n" << r.out;
        EXPECT_EQ(r.out.find("libopen-pal"), std::string::npos) << program << ":\n" << r.out;
    }
}

} // namespace
} // namespace pyramid
