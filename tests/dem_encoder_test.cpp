// preprocessDem as a library: closed-loop reconstruction equals the CPU producer bit for bit,
// the error bound holds at every level, output is identical for any thread count, overflow is
// detected, non-square and nodata inputs are handled; what the encoder skips beyond a partial
// source's heights gives the file that encoding every sample gives.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <tuple>

#include "formats/error.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/aperture/aperture.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"
#include "tests/support/sparse_sets.hpp"

namespace pyramid {
namespace {

using Recon = std::map<std::tuple<int, int, int>, std::vector<float>>;

DemEncodeOptions smallOptions() {
    DemEncodeOptions o;
    o.tileSize = 8;
    o.rootTileSize = 4; // minLevel 1
    return o;
}

// 257 x 257 samples: N = 256 = 4 << 6, so maxLevel 6 and, with minLevel 1, more levels than
// one in-memory pass: the subtree pass runs too.
struct Fixture {
    test::TempDir dir;
    std::string input = dir.file("dem.tif");
    std::vector<float> heights = test::syntheticHeights(257, 257);
    Fixture() { test::writeFloatRaster(input, 257, 257, heights); }
};

TEST(DemEncoder, ReconstructionEqualsProducerBitForBit) {
    Fixture f;
    Recon recon;
    DemEncodeOptions o = smallOptions();
    o.scale = 0.25;
    o.reconstruction = [&](int l, int tx, int ty, const std::vector<float>& z) { recon[{l, tx, ty}] = z; };
    const std::string out = f.dir.file("DEM.dat");
    const DemReport report = encodeDem(f.input, out, o);
    EXPECT_EQ(report.header.maxLevel, 6);
    EXPECT_EQ(report.header.minLevel, 1);
    EXPECT_EQ(report.sampling, "input samples are the finest grid samples (no resampling)");
    ASSERT_EQ(static_cast<int64_t>(recon.size()), report.tiles);
    const ResidualHeader h = report.header;
    for (int l = 0; l <= h.maxLevel; ++l) {
        const FileLevelProducer producer = makeFileLevelProducer(out, l);
        const int side = l < h.minLevel ? 1 : 1 << (l - h.minLevel);
        for (int ty = 0; ty < side; ++ty) {
            for (int tx = 0; tx < side; ++tx) {
                const auto tile = producer.fileTile(l, tx, ty);
                const std::vector<float>& mine = recon.at({l, tx, ty});
                ASSERT_EQ(mine.size(), tile->zf.size());
                ASSERT_EQ(std::memcmp(mine.data(), tile->zf.data(), mine.size() * sizeof(float)), 0)
                    << "tile (" << l << "," << tx << "," << ty << ")";
            }
        }
    }
}

TEST(DemEncoder, ErrorBoundAtEveryLevelAndFinestLevelIsTheInput) {
    Fixture f;
    DemEncodeOptions o = smallOptions();
    o.scale = 0.1;
    Recon recon;
    o.reconstruction = [&](int l, int tx, int ty, const std::vector<float>& z) {
        if (l == 6) {
            recon[{l, tx, ty}] = z;
        }
    };
    const DemReport report = encodeDem(f.input, f.dir.file("DEM.dat"), o);
    for (const ResidualLevelReport& l : report.levels) {
        EXPECT_GT(l.samples, 0);
        EXPECT_LE(l.maxError, 0.05 + 1e-3) << "level " << l.level;
    }
    EXPECT_EQ(report.levels.back().samples, 257 * 257);
    // Finest sample (x, y) is input column x, row 256 - y.
    const int S = 8 + 5;
    for (int ty = 0; ty < 32; ty += 7) {
        for (int tx = 0; tx < 32; tx += 5) {
            const auto& z = recon.at({6, tx, ty});
            for (int j = 2; j <= 10; ++j) {
                for (int i = 2; i <= 10; ++i) {
                    const int x = tx * 8 + i - 2, y = ty * 8 + j - 2;
                    const float src = f.heights[static_cast<size_t>(x + (256 - y) * 257)];
                    ASSERT_NEAR(z[static_cast<size_t>(i + j * S)], src, 0.05 + 1e-3);
                }
            }
        }
    }
    const DemVerifyReport verify = verifyDem(f.dir.file("DEM.dat"), f.input, {});
    EXPECT_TRUE(verify.ok());
    ASSERT_EQ(verify.levels.size(), report.levels.size());
    for (size_t l = 0; l < verify.levels.size(); ++l) {
        EXPECT_EQ(verify.levels[l].maxError, report.levels[l].maxError);
        EXPECT_EQ(verify.levels[l].samples, report.levels[l].samples);
        // The same errors, summed in another order.
        EXPECT_NEAR(verify.levels[l].rmsError, report.levels[l].rmsError, 1e-12 + 1e-9 * report.levels[l].rmsError);
        EXPECT_GT(report.levels[l].rmsError, 0.0) << "level " << l;
    }
}

TEST(DemEncoder, IdenticalBytesForAnyThreadCount) {
    Fixture f;
    DemEncodeOptions o = smallOptions();
    o.threads = 1;
    encodeDem(f.input, f.dir.file("one.dat"), o);
    o.threads = 2;
    encodeDem(f.input, f.dir.file("two.dat"), o);
    o.threads = 3;
    encodeDem(f.input, f.dir.file("three.dat"), o);
    const std::string one = test::readFile(f.dir.file("one.dat"));
    EXPECT_GT(one.size(), 1000u);
    EXPECT_EQ(one, test::readFile(f.dir.file("two.dat")));
    EXPECT_EQ(one, test::readFile(f.dir.file("three.dat")));
}

TEST(DemEncoder, OverflowIsAnErrorOrChoosesAScale) {
    test::TempDir dir;
    std::vector<float> heights = test::syntheticHeights(65, 65, 60000.0f);
    test::writeFloatRaster(dir.file("high.tif"), 65, 65, heights);
    DemEncodeOptions o = smallOptions();
    o.scale = 1.0;
    try {
        encodeDem(dir.file("high.tif"), dir.file("DEM.dat"), o);
        FAIL() << "no overflow reported";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("overflow"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind("scale: ", 0), 0u) << e.what(); // OptionError("scale")
        EXPECT_NE(std::string(e.what()).find("or more (a largest error of "), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("DEM.dat")));
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1); // only the input
    o.autoScale = true;
    const DemReport report = encodeDem(dir.file("high.tif"), dir.file("DEM.dat"), o);
    const double s = report.header.scale;
    EXPECT_GT(s, 1.0);
    // A 1-2-5 step; the next smaller one would have overflowed.
    const double mantissa = s / std::pow(10.0, std::floor(std::log10(s)));
    EXPECT_TRUE(std::fabs(mantissa - 1) < 1e-9 || std::fabs(mantissa - 2) < 1e-9 || std::fabs(mantissa - 5) < 1e-9);
    for (const ResidualLevelReport& l : report.levels) {
        EXPECT_LE(l.maxAbsResidual, 32767);
        EXPECT_LE(l.maxError, s / 2 + 0.01);
    }
    EXPECT_TRUE(verifyDem(dir.file("DEM.dat"), dir.file("high.tif"), {}).ok());
}

// The automatic scale's first guess comes from the in-memory grid of levels 0..C, which misses
// spikes at odd samples: the subtrees overflow, and the next attempt encodes levels 0..C again
// from the grid sampled again (it is released while the subtrees are encoded).
TEST(DemEncoder, AnAttemptAfterASubtreesOverflowIsTheBuildAtItsScale) {
    test::TempDir dir;
    const int w = 257;
    std::vector<float> heights = test::syntheticHeights(w, w, 500.0f);
    for (int k = 0; k < 4; ++k) {
        heights[static_cast<size_t>((w - 6 - 2 * k) + (3 + 2 * k) * w)] = 4.0e5f * static_cast<float>(k + 1);
    }
    test::writeFloatRaster(dir.file("spikes.tif"), w, w, heights);
    DemEncodeOptions o = smallOptions();
    o.threads = 2;
    o.autoScale = true;
    const DemReport report = encodeDem(dir.file("spikes.tif"), dir.file("auto.dat"), o);
    ASSERT_GT(report.scalesTried.size(), 1u);
    EXPECT_TRUE(verifyDem(dir.file("auto.dat"), dir.file("spikes.tif"), {}).ok());
    o.autoScale = false;
    o.scale = report.header.scale;
    const DemReport given = encodeDem(dir.file("spikes.tif"), dir.file("given.dat"), o);
    EXPECT_EQ(given.scalesTried.size(), 1u);
    EXPECT_EQ(test::readFile(dir.file("auto.dat")), test::readFile(dir.file("given.dat")));
}

using test::Patch;

TEST(ResidualEncoder, WhatNoHeightReachesIsSkippedIntoTheFileOfEverySample) {
    test::TempDir dir;
    ResidualPyramidJob job;
    job.header.tileSize = 32;
    job.header.minLevel = 3; // root tile of 4 intervals
    job.header.maxLevel = 10; // N = 4096; the grid holds every 16th sample (C = 6), in 5 bands of 64 rows
    job.input = "patch";
    ResidualEncodeOptions o;
    o.scale = 0.25;
    o.threads = 2;
    // Across a band of the grid (rows 1024 apart) and footprints' blocks; a patch near a corner.
    const int64_t patches[][4] = {{1500, 900, 1800, 1200}, {3900, 3950, 4096, 4096}};
    for (const auto& p : patches) {
        for (const GridEdges edges : {GridEdges::Clamped, GridEdges::Folded}) {
            std::string files[2];
            for (const bool exact : {true, false}) {
                const Patch heights(p[0], p[1], p[2], p[3], exact);
                job.heights = &heights;
                job.edges = edges;
                files[exact ? 0 : 1] = dir.file(exact ? "exact.dat" : "every.dat");
                ResidualPyramidReport report;
                o.layout = PyramidLayout::Dense; // one file of every tile, to compare byte for byte
                encodeResidualPyramid(job, files[exact ? 0 : 1], o, report);
                EXPECT_GT(report.nodataFilled, 4000 * 4000);
            }
            EXPECT_TRUE(test::readFile(files[0]) == test::readFile(files[1]))
                << "patch at " << p[0] << "," << p[1] << (edges == GridEdges::Folded ? ", folded" : "");
        }
    }
}

TEST(ResidualEncoder, SparseLayoutStoresWhatTheHeightsReachAndTheDenseFilesTiles) {
    test::TempDir dir;
    ResidualPyramidJob job;
    job.header.tileSize = 32;
    job.header.minLevel = 3;
    job.header.maxLevel = 10; // N = 4096, 21848 tiles
    job.input = "patch";
    ResidualEncodeOptions o;
    o.scale = 0.25;
    o.threads = 2;
    const Patch heights(1500, 900, 1800, 1200, true);
    job.heights = &heights;
    for (const GridEdges edges : {GridEdges::Clamped, GridEdges::Folded}) {
        job.edges = edges;
        ResidualPyramidReport dense, sparse;
        o.layout = PyramidLayout::Dense;
        encodeResidualPyramid(job, dir.file("dense.dat"), o, dense);
        o.layout = PyramidLayout::Sparse;
        encodeResidualPyramid(job, dir.file("sparse.dat"), o, sparse);
        // Files only where the patch is: a main file of the top levels and regions nested in it.
        ASSERT_GE(sparse.files.size(), 2u);
        EXPECT_EQ(sparse.files[0].first, "sparse.dat");
        EXPECT_LT(sparse.bytes * 2, dense.bytes);
        EXPECT_LT(sparse.tiles * 5, dense.tiles);
        EXPECT_TRUE(std::filesystem::exists(dir.file("sparse.dat.regions.json")));
        // preprocessAperture needs every tile of the finest level: refused in one line naming the
        // set (the whole plane at the patch's resolution), nothing written.
        ApertureEncodeOptions ao;
        ao.size = 4096.0;
        try {
            encodeApertureFile(dir.file("sparse.dat"), dir.file("aperture.dat"), ao);
            ADD_FAILURE() << "the aperture of a sparse set was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("only in places"), std::string::npos) << e.what();
        }
        EXPECT_FALSE(std::filesystem::exists(dir.file("aperture.dat")));
        const int64_t beyond = test::expectSparseSetOfDense(dir.file("dense.dat"), dir.file("sparse.dat"));
        EXPECT_GT(beyond, 15000);
        // Heights at points come from the deepest file holding them: the finest level in the
        // patch, the same height as the dense file's; a coarser one beyond it.
        const PointHeight in = setHeightAt(dir.file("sparse.dat"), 1650.0 / 4096, 1050.0 / 4096);
        EXPECT_EQ(in.level, 10);
        EXPECT_EQ(in.height, setHeightAt(dir.file("dense.dat"), 1650.0 / 4096, 1050.0 / 4096).height);
        EXPECT_LT(setHeightAt(dir.file("sparse.dat"), 0.9, 0.1).level, 10);
        // The same statistics: the tiles left out hold no source sample.
        ASSERT_EQ(sparse.levels.size(), dense.levels.size());
        for (size_t l = 0; l < dense.levels.size(); ++l) {
            EXPECT_EQ(sparse.levels[l].samples, dense.levels[l].samples) << "level " << l;
            EXPECT_EQ(sparse.levels[l].maxError, dense.levels[l].maxError) << "level " << l;
        }
        // Any thread count, the same files.
        const std::string main = test::readFile(dir.file("sparse.dat"));
        o.threads = 1;
        ResidualPyramidReport again;
        encodeResidualPyramid(job, dir.file("sparse.dat"), o, again);
        EXPECT_EQ(test::readFile(dir.file("sparse.dat")), main);
        ASSERT_EQ(again.files, sparse.files);
        for (const auto& [name, bytes] : sparse.files) {
            EXPECT_EQ(std::filesystem::file_size(dir.file(name)), bytes) << name;
        }
        o.threads = 2;
    }
}

TEST(ResidualEncoder, SparseLayoutOfHeightsThatFillThePyramidIsTheDenseFile) {
    test::TempDir dir;
    ResidualPyramidJob job;
    job.header.tileSize = 32;
    job.header.minLevel = 3;
    job.header.maxLevel = 7;
    job.input = "patch";
    ResidualEncodeOptions o;
    o.scale = 0.25;
    const Patch heights(0, 0, 512, 512, false); // may have heights everywhere
    job.heights = &heights;
    ResidualPyramidReport dense, sparse;
    o.layout = PyramidLayout::Dense;
    encodeResidualPyramid(job, dir.file("dense.dat"), o, dense);
    o.layout = PyramidLayout::Sparse;
    encodeResidualPyramid(job, dir.file("sparse.dat"), o, sparse);
    EXPECT_TRUE(sparse.files.empty());
    EXPECT_FALSE(std::filesystem::exists(dir.file("sparse.dat.regions.json")));
    EXPECT_EQ(test::readFile(dir.file("sparse.dat")), test::readFile(dir.file("dense.dat")));
}

TEST(DemEncoder, NonSquareInputKeepsItsAspectRatio) {
    test::TempDir dir;
    const int w = 130, h = 70;
    test::writeFloatRaster(dir.file("wide.tif"), w, h, test::syntheticHeights(w, h));
    DemEncodeOptions o = smallOptions();
    const DemReport report = encodeDem(dir.file("wide.tif"), dir.file("DEM.dat"), o);
    EXPECT_EQ(report.header.maxLevel, 6); // 130 samples across: 4 << 5 + 1 = 129 is one short
    EXPECT_NE(report.sampling.find("aspect ratio kept"), std::string::npos);
    // The input spans the 257 finest samples across and 69 * 256 / 129 rows of them: the
    // southern rest is filled.
    EXPECT_GT(report.nodataFilled, 257 * 100);
    EXPECT_TRUE(verifyDem(dir.file("DEM.dat"), dir.file("wide.tif"), {}).ok());
    o.stretch = true;
    const DemReport stretched = encodeDem(dir.file("wide.tif"), dir.file("S.dat"), o);
    EXPECT_EQ(stretched.nodataFilled, 0);
    DemVerifyOptions vo;
    vo.stretch = true;
    EXPECT_TRUE(verifyDem(dir.file("S.dat"), dir.file("wide.tif"), vo).ok());
}

TEST(DemEncoder, NodataHolesAreFilledSmoothly) {
    test::TempDir dir;
    const int w = 129;
    std::vector<float> heights = test::syntheticHeights(w, w, 200.0f);
    float validMin = 1e30f, validMax = -1e30f;
    int hole = 0;
    for (int y = 0; y < w; ++y) {
        for (int x = 0; x < w; ++x) {
            float& v = heights[static_cast<size_t>(x + y * w)];
            if ((x - 60) * (x - 60) + (y - 50) * (y - 50) < 15 * 15) {
                v = -32768.0f;
                ++hole;
            } else {
                validMin = std::min(validMin, v);
                validMax = std::max(validMax, v);
            }
        }
    }
    test::writeFloatRaster(dir.file("holes.tif"), w, w, heights);
    DemEncodeOptions o = smallOptions();
    o.nodata = -32768.0;
    float low = 1e30f, high = -1e30f;
    o.reconstruction = [&](int l, int, int, const std::vector<float>& z) {
        if (l == 5) {
            for (float v : z) {
                low = std::min(low, v);
                high = std::max(high, v);
            }
        }
    };
    const DemReport report = encodeDem(dir.file("holes.tif"), dir.file("DEM.dat"), o);
    EXPECT_EQ(report.nodataFilled, hole);
    const float range = validMax - validMin;
    EXPECT_GT(low, validMin - 0.25f * range);
    EXPECT_LT(high, validMax + 0.25f * range);
    DemVerifyOptions vo;
    vo.nodata = -32768.0;
    EXPECT_TRUE(verifyDem(dir.file("DEM.dat"), dir.file("holes.tif"), vo).ok());
}

TEST(DemEncoder, OddSizesResample) {
    test::TempDir dir;
    test::writeFloatRaster(dir.file("odd.tif"), 101, 101, test::syntheticHeights(101, 101));
    DemEncodeOptions o = smallOptions();
    const DemReport report = encodeDem(dir.file("odd.tif"), dir.file("DEM.dat"), o);
    EXPECT_EQ(report.header.maxLevel, 5); // 4 << 5 + 1 = 129 >= 101
    EXPECT_NE(report.sampling.find("bilinear"), std::string::npos);
    EXPECT_EQ(report.nodataFilled, 0);
    EXPECT_TRUE(verifyDem(dir.file("DEM.dat"), dir.file("odd.tif"), {}).ok());
}

} // namespace
} // namespace pyramid
