// `preprocessDem --tile-size auto` (libpyramid/encode/dem/dem_tile_fit.hpp): the tiles and
// levels chosen for common DEM sizes make the finest level the input's own grid; the encoded
// pyramids round-trip within scale/2 without resampling; inputs that no grid fits get the least
// resampling (checked against every tiling the format allows); cube faces refuse `auto`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/dem/dem_tile_fit.hpp"
#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::programPath;
using test::run;

std::string quoted(const std::string& s) { return "'" + s + "'"; }

struct Expected {
    int side; // samples per side of a square input
    int tileSize;
    int rootTileSize;
    int minLevel;
    int maxLevel;
};

TEST(DemTileFit, CommonSizesMakeTheFinestLevelTheInputGrid) {
    const Expected cases[] = {
        // The root stays even: 150 / 2 = 75 would not be.
        {1201, 150, 150, 0, 3},    // SRTM 3 arc-seconds: 1200 = 150 x 8
        {3601, 450, 450, 0, 3},    // SRTM 1 arc-second: 3600 = 450 x 8, no tile of 250 or less fits
        {10801, 1350, 1350, 0, 3}, // 1/3 arc-second 1-degree tiles: 10800 = 1350 x 8
        {2049, 128, 32, 2, 6},
        {4097, 128, 32, 2, 7},
        {513, 128, 32, 2, 4},
        {257, 128, 32, 2, 3},
        {769, 192, 24, 3, 5},    // the defaults' own fit (doc/dem-encoding.md's example)
        {3, 2, 2, 0, 0},
    };
    for (const Expected& e : cases) {
        SCOPED_TRACE(e.side);
        const DemTileFit fit = fitDemTiles(e.side, e.side, false, "dem.tif");
        EXPECT_EQ(fit.tileSize, e.tileSize);
        EXPECT_EQ(fit.rootTileSize, e.rootTileSize);
        EXPECT_EQ(fit.minLevel, e.minLevel);
        EXPECT_EQ(fit.maxLevel, e.maxLevel);
        EXPECT_TRUE(fit.exact);
        EXPECT_DOUBLE_EQ(fit.resampling(), 1.0);
        EXPECT_EQ(fit.prolandReadable(), e.tileSize <= 250);
        // The finest level's samples per side are the input's: R << maxLevel = side - 1.
        EXPECT_EQ(fit.intervals + 1, e.side);
        EXPECT_EQ(static_cast<int64_t>(fit.rootTileSize) << fit.maxLevel, e.side - 1);
        EXPECT_EQ(fit.rootTileSize << fit.minLevel, fit.tileSize);
        EXPECT_EQ(fit.rootTileSize % 2, 0);
        // The header the encoder plans from the option is the fit's.
        DemEncodeOptions o;
        o.fitTiles = true;
        RasterInfo info;
        info.width = info.height = e.side;
        DemTileFit planned;
        const ResidualHeader h = planDemPyramid(info, o, "dem.tif", &planned);
        EXPECT_EQ(h.tileSize, e.tileSize);
        EXPECT_EQ(h.minLevel, e.minLevel);
        EXPECT_EQ(h.maxLevel, e.maxLevel);
        EXPECT_EQ(planned.describe(), fit.describe());
        EXPECT_NE(fit.describe().find("no resampling"), std::string::npos) << fit.describe();
    }
}

TEST(DemTileFit, NonSquareInputsFitTheirLongerSide) {
    // Aspect kept: the input sits at the north-west corner, sample for sample.
    DemTileFit fit = fitDemTiles(1201, 601, false, "dem.tif");
    EXPECT_EQ(fit.tileSize, 150);
    EXPECT_EQ(fit.intervals, 1200);
    EXPECT_TRUE(fit.exact);
    fit = fitDemTiles(300, 513, false, "dem.tif");
    EXPECT_EQ(fit.tileSize, 128);
    EXPECT_EQ(fit.maxLevel, 4);
    EXPECT_TRUE(fit.exact);
    // Stretched, the shorter side is resampled whatever the tiles: the longer side still fits.
    fit = fitDemTiles(1201, 601, true, "dem.tif");
    EXPECT_EQ(fit.intervals, 1200);
    EXPECT_FALSE(fit.exact);
    EXPECT_NE(fit.describe().find("stretched"), std::string::npos) << fit.describe();
    // A square input stretched is the same map.
    EXPECT_TRUE(fitDemTiles(513, 513, true, "dem.tif").exact);
}

// Every (tile size, power of two) the encoder takes, as the rule ranks them: the exact fits
// with readable tiles (largest tile first), then exact fits with larger tiles (smallest
// first), else the readable tiling with the fewest finest intervals N >= L (largest tile on a
// tie). The rule is checked against this search over all L up to 5000 and a few large ones.
struct Tiling {
    int64_t T = 0;
    int k = 0;
};

Tiling bruteForce(int64_t L) {
    Tiling readableExact, unreadableExact, leastResampled;
    int64_t leastN = INT64_MAX;
    for (int k = 0; k <= 24; ++k) {
        for (int64_t T = 2; T <= 8192; T += 2) {
            const int64_t N = T << k;
            if (N > 2 * L + 512) {
                break; // beyond every candidate: N only grows with T
            }
            if (N == L) {
                if (T <= 250 && T > readableExact.T) {
                    readableExact = {T, k};
                }
                if (T > 250 && (unreadableExact.T == 0 || T < unreadableExact.T)) {
                    unreadableExact = {T, k};
                }
            }
            if (T <= 250 && N >= L && (N < leastN || (N == leastN && T > leastResampled.T))) {
                leastN = N;
                leastResampled = {T, k};
            }
        }
    }
    return readableExact.T ? readableExact : unreadableExact.T ? unreadableExact : leastResampled;
}

TEST(DemTileFit, WithoutAnExactFitTheLeastResampling) {
    std::vector<int64_t> lengths;
    for (int64_t L = 1; L <= 5000; ++L) {
        lengths.push_back(L);
    }
    for (int64_t L : {16383, 16384, 21600, 43200, 86400, 100001}) {
        lengths.push_back(L);
    }
    int inexact = 0;
    for (const int64_t L : lengths) {
        const DemTileFit fit = fitDemTiles(static_cast<int>(L + 1), static_cast<int>(L + 1), false, "dem.tif");
        const Tiling best = bruteForce(L);
        ASSERT_EQ(fit.tileSize, best.T) << "L " << L;
        ASSERT_EQ(fit.maxLevel - fit.minLevel, best.k) << "L " << L;
        ASSERT_EQ(fit.intervals, best.T << best.k) << "L " << L;
        ASSERT_EQ(fit.exact, fit.intervals == L) << "L " << L;
        ASSERT_GE(fit.intervals, L) << "L " << L; // never fewer samples than the input's
        inexact += fit.exact ? 0 : 1;
        // The root is even, at least 24 unless the tile cannot be halved to an even one that is.
        ASSERT_EQ(fit.rootTileSize % 2, 0) << "L " << L;
        ASSERT_TRUE(fit.rootTileSize >= 24 || fit.rootTileSize == fit.tileSize) << "L " << L;
        if (fit.rootTileSize / 2 >= 24) {
            ASSERT_NE(fit.rootTileSize % 4, 0) << "L " << L; // a smaller even root was possible
        }
        if (!fit.exact) {
            ASSERT_TRUE(fit.prolandReadable()) << "L " << L;
            // Less than 2^(k+1) more intervals, and k is small enough that L > 125 x 2^k.
            ASSERT_LT(fit.intervals - L, int64_t{2} << (fit.maxLevel - fit.minLevel)) << "L " << L;
            if (L >= 125) {
                ASSERT_LT(fit.resampling(), 1.0 + 2.0 / 125.0) << "L " << L;
            }
        }
    }
    EXPECT_GT(inexact, 2000); // every odd L among them
    // 1000 samples (999 intervals, odd): 250-tiles, 1000 intervals.
    const DemTileFit fit = fitDemTiles(1000, 1000, false, "dem.tif");
    EXPECT_EQ(fit.tileSize, 250);
    EXPECT_EQ(fit.intervals, 1000);
    EXPECT_FALSE(fit.exact);
    EXPECT_NE(fit.describe().find("least resampling"), std::string::npos) << fit.describe();
}

TEST(DemTileFit, TooSmallInputsAndContradictingOptionsAreRefused) {
    EXPECT_THROW(fitDemTiles(1, 100, false, "dem.tif"), Error);
    DemEncodeOptions o;
    o.fitTiles = true;
    o.maxLevel = 3;
    try {
        o.validate();
        ADD_FAILURE() << "fitTiles with maxLevel validated";
    } catch (const OptionError& e) {
        EXPECT_EQ(e.option(), "maxLevel");
    }
    o.maxLevel.reset();
    o.dstMaxLevel = 1;
    EXPECT_THROW(o.validate(), OptionError);
    // The tile fields are ignored under fitTiles.
    o.dstMaxLevel.reset();
    o.tileSize = 7;
    EXPECT_NO_THROW(o.validate());
}

// Encodes a side x side synthetic DEM with fitTiles and checks the pyramid: the fit's header,
// the input's samples as the finest grid, and every level within scale/2 (pyramid verify's
// library call).
void expectRoundTrip(int side, int tileSize, int maxLevel) {
    test::TempDir dir;
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, side, side, test::syntheticHeights(side, side, 2000.0f));
    DemEncodeOptions o;
    o.fitTiles = true;
    o.scale = 0.5;
    o.threads = 2;
    int chosen = 0;
    o.tileFitChosen = [&](const DemTileFit& fit) { chosen = fit.tileSize; };
    const std::string out = dir.file("DEM.dat");
    const DemReport report = encodeDem(input, out, o);
    EXPECT_EQ(chosen, tileSize);
    ASSERT_TRUE(report.tileFit.has_value());
    EXPECT_TRUE(report.tileFit->exact);
    EXPECT_EQ(report.header.tileSize, tileSize);
    EXPECT_EQ(report.header.maxLevel, maxLevel);
    EXPECT_EQ(report.finestSamples, static_cast<int64_t>(side) * side);
    EXPECT_EQ(report.nodataFilled, 0);
    EXPECT_EQ(report.sampling, "input samples are the finest grid samples (no resampling)");
    const nlohmann::json json = toJson(report);
    EXPECT_EQ(json["tile_fit"]["tile_size"], tileSize);
    EXPECT_EQ(json["tile_fit"]["finest_samples_per_side"], side);
    EXPECT_EQ(json["tile_fit"]["exact"], true);
    const DemVerifyReport verified = verifyDem(out, input, DemVerifyOptions{});
    EXPECT_TRUE(verified.ok());
    ASSERT_EQ(static_cast<int>(verified.levels.size()), maxLevel + 1);
    for (const DemVerifyLevel& l : verified.levels) {
        EXPECT_LE(l.maxError, 0.25 + 1e-3) << "level " << l.level;
        EXPECT_EQ(l.beyondBound, 0) << "level " << l.level;
    }
    EXPECT_EQ(verified.levels.back().samples, static_cast<int64_t>(side) * side);
}

TEST(DemTileFit, SyntheticDemsRoundTripOnTheirOwnGrid) {
    expectRoundTrip(257, 128, 3);
    expectRoundTrip(513, 128, 4);
    expectRoundTrip(301, 150, 1); // 300 = 150 x 2: a tile that is no power of two, root 150
    expectRoundTrip(97, 96, 2);   // 96 = 96 x 1: root 24, minLevel 2
}

TEST(DemTileFit, NonSquareInputIsCodedSampleForSample) {
    // 129 x 65: the finest level is 129 x 129 with the input at the north-west corner, each
    // input sample a finest sample (its reconstruction within scale/2), the rest nodata.
    test::TempDir dir;
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, 129, 65, test::syntheticHeights(129, 65, 500.0f));
    DemEncodeOptions o;
    o.fitTiles = true;
    o.scale = 0.25;
    const DemReport report = encodeDem(input, dir.file("DEM.dat"), o);
    ASSERT_TRUE(report.tileFit.has_value());
    EXPECT_TRUE(report.tileFit->exact);
    EXPECT_EQ(report.header.tileSize, 128);
    EXPECT_EQ(report.nodataFilled, 129 * 129 - 129 * 65);
    EXPECT_NE(report.sampling.find("no resampling"), std::string::npos) << report.sampling;
    EXPECT_TRUE(verifyDem(dir.file("DEM.dat"), input, DemVerifyOptions{}).ok());
}

TEST(DemTileFit, SphericalDemRefusesAuto) {
    test::TempDir dir;
    const std::string input = dir.file("map.tif");
    test::writeFloatRaster(input, 64, 32, test::syntheticHeights(64, 32));
    SphericalDemOptions o;
    o.dem.fitTiles = true;
    try {
        encodeSphericalDem(input, dir.file("out"), o);
        ADD_FAILURE() << "cube faces took fitTiles";
    } catch (const OptionError& e) {
        EXPECT_EQ(e.option(), "tileSize");
        EXPECT_NE(e.problem().find("'auto'"), std::string::npos) << e.problem();
    }
    // The program: a usage error on one line, before any work.
    const auto r = run(programPath("preprocessSphericalDem") + " " + quoted(input) + " -o " + quoted(dir.file("out")) +
                       " --tile-size auto");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("--tile-size"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("'auto' fits a planar input (preprocessDem)"), std::string::npos) << r.err;
    EXPECT_FALSE(test::fileExists(dir.file("out")));
}

class DemTileFitCli : public ::testing::Test {
protected:
    test::TempDir dir;

    test::RunResult encode(const std::string& input, const std::string& args) {
        return run(programPath("preprocessDem") + " " + quoted(input) + " -o " + quoted(dir.file("DEM.dat")) + " " + args);
    }
};

TEST_F(DemTileFitCli, ReportsTheChoiceOnStderrAndInTheReport) {
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, 257, 257, test::syntheticHeights(257, 257));
    auto r = encode(input, "--tile-size auto --report " + quoted(dir.file("r.json")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("--tile-size auto: tile size 128, root tile size 32 (minLevel 2), maxLevel 3: the finest "
                         "level is the input's 257x257 grid, no resampling"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    auto report = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_EQ(report["tile_fit"]["tile_size"], 128);
    EXPECT_EQ(report["tile_fit"]["root_tile_size"], 32);
    EXPECT_EQ(report["tile_fit"]["proland_readable"], true);
    EXPECT_EQ(report["header"]["tile_size"], 128);
    EXPECT_EQ(report["finest_samples"], 257 * 257);
    const auto verified = run(programPath("pyramid") + " verify " + quoted(dir.file("DEM.dat")) + " --source " + quoted(input));
    EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
    // --quiet says nothing; without auto the report's tile_fit is null.
    r = encode(input, "--tile-size auto -q");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    r = encode(input, "-q --report " + quoted(dir.file("r.json")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    report = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_TRUE(report["tile_fit"].is_null());
    EXPECT_EQ(report["header"]["tile_size"], 192);
}

TEST_F(DemTileFitCli, LargeExactTilesWarnAndOddSizesSayTheyResample) {
    // 503 samples: 502 = 2 x 251, so the only exact tiles are 502 intervals: the warning path.
    std::string input = dir.file("wide.tif");
    test::writeFloatRaster(input, 503, 503, test::syntheticHeights(503, 503));
    auto r = encode(input, "--tile-size auto --report " + quoted(dir.file("r.json")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("--tile-size auto: tile size 502,"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("warning: tiles of 507 samples"), std::string::npos) << r.err;
    auto report = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_EQ(report["tile_fit"]["exact"], true);
    EXPECT_EQ(report["tile_fit"]["proland_readable"], false);
    // 66 samples: 65 intervals (odd) fit no tiling; 66 intervals resample least.
    input = dir.file("odd.tif");
    test::writeFloatRaster(input, 66, 66, test::syntheticHeights(66, 66));
    r = encode(input, "--tile-size auto --report " + quoted(dir.file("r.json")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("the least resampling: 66x66 input samples onto a 67x67 finest grid"), std::string::npos)
        << r.err;
    report = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_EQ(report["tile_fit"]["exact"], false);
    EXPECT_EQ(report["tile_fit"]["tile_size"], 66);
    EXPECT_EQ(report["tile_fit"]["finest_samples_per_side"], 67);
    EXPECT_NE(report["sampling"].get<std::string>().find("bilinear resampling"), std::string::npos);
}

TEST_F(DemTileFitCli, AutoRefusesTheOptionsItChooses) {
    const std::string input = dir.file("dem.tif");
    test::writeFloatRaster(input, 65, 65, test::syntheticHeights(65, 65));
    for (const auto& [args, mention] : std::vector<std::pair<std::string, std::string>>{
             {"--tile-size auto --root-tile-size 16", "--root-tile-size: is chosen by --tile-size auto"},
             {"--tile-size auto --max-level 3", "--max-level: is chosen by --tile-size auto"},
             {"--tile-size auto --dst-max-level 1", "--dst-max-level: is chosen by --tile-size auto"}}) {
        const auto r = encode(input, args);
        EXPECT_EQ(r.exitCode, 1) << args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(mention), std::string::npos) << args << "\n" << r.err;
        EXPECT_FALSE(test::fileExists(dir.file("DEM.dat"))) << args;
    }
    const auto r = encode(input, "--tile-size big");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("'big' is not a whole number of intervals nor 'auto'"), std::string::npos) << r.err;
}

TEST_F(DemTileFitCli, PartsOfASplitBuildChooseAlikeAndMergeIntoTheSingleRunsFile) {
    const std::string input = dir.file("dem.tif");
    // 128-tiles, maxLevel 4: the level-4 subtrees are shared between the parts.
    test::writeFloatRaster(input, 513, 513, test::syntheticHeights(513, 513));
    ASSERT_EQ(run(programPath("preprocessDem") + " -q " + quoted(input) + " -o " + quoted(dir.file("one.dat")) +
                  " --tile-size auto").exitCode, 0);
    for (const char* part : {"0/2", "1/2"}) {
        const auto r = encode(input, std::string("-q --tile-size auto --part ") + part);
        ASSERT_EQ(r.exitCode, 0) << r.err;
    }
    const auto merged = run(programPath("pyramid") + " merge " + quoted(dir.file("DEM.dat.part-0-of-2")) + " " +
                            quoted(dir.file("DEM.dat.part-1-of-2")));
    ASSERT_EQ(merged.exitCode, 0) << merged.err;
    const std::string one = test::readFile(dir.file("one.dat"));
    EXPECT_GT(one.size(), 1000u);
    EXPECT_EQ(test::readFile(dir.file("DEM.dat")), one);
}

// The real SRTM tile (1201 x 1201 int16): 150-tiles, the input as the finest level, and every
// level within scale/2 by `pyramid verify`.
TEST_F(DemTileFitCli, MountRainierFitsWithoutResampling) {
    const std::string rainier = test::sharedFixturePath("inputs/mt_rainier_90m.tif");
    if (rainier.empty()) {
        GTEST_SKIP() << "../shared/fixtures is not there";
    }
    const auto r = encode(rainier, "-q --tile-size auto --scale 1 --report " + quoted(dir.file("r.json")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto report = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_EQ(report["tile_fit"]["tile_size"], 150);
    EXPECT_EQ(report["tile_fit"]["root_tile_size"], 150);
    EXPECT_EQ(report["tile_fit"]["exact"], true);
    EXPECT_EQ(report["header"]["min_level"], 0);
    EXPECT_EQ(report["header"]["max_level"], 3);
    EXPECT_EQ(report["finest_samples"], 1201 * 1201);
    EXPECT_EQ(report["sampling"], "input samples are the finest grid samples (no resampling)");
    for (const auto& l : report["levels"]) {
        EXPECT_LE(l["max_error"].get<double>(), 0.5 + 1e-3) << l;
    }
    const auto verified =
        run(programPath("pyramid") + " verify " + quoted(dir.file("DEM.dat")) + " --source " + quoted(rainier) + " --json");
    EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
    const auto v = nlohmann::json::parse(verified.out);
    EXPECT_EQ(v["levels"].size(), 4u) << verified.out;
}

} // namespace
} // namespace pyramid
