// Region sets written by the DEM preprocessors (--max-file-bytes): every file within the limit,
// each a valid region file of the format (doc/format.md 1.4), the index listing them, and the
// set rebuilding the single file's elevations bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/pyramid_set.hpp"
#include "formats/residual_file.hpp"
#include "formats/residual_set.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/capi/pyramid.h"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/residual_producer.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::TempDir;

struct Built {
    std::vector<std::string> regions; // paths, in the index's order
    nlohmann::json index;
};

Built readSet(const std::string& dir, const std::string& main) {
    std::ifstream in(dir + "/" + main + ".regions.json");
    Built b;
    b.index = nlohmann::json::parse(in);
    for (const auto& r : b.index.at("regions")) {
        b.regions.push_back(dir + "/" + r.at("file").get<std::string>());
    }
    return b;
}

// Every elevation tile of every level, from `main` with `regions`, as the single file gives it.
void expectSameElevations(const std::string& single, const std::string& main, const std::vector<std::string>& regions) {
    const ResidualHeader h = ResidualFileReader::open(single)->header();
    ElevationProducerOptions eo;
    ResidualProducerOptions ro;
    ro.delta = h.minLevel; // elevation tiles of the file's tile size
    const auto one = std::make_shared<ResidualProducer>(single, std::vector<std::string>{}, ro);
    const auto set = std::make_shared<ResidualProducer>(main, regions, ro);
    ElevationProducer a(one, eo), b(set, eo);
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

TEST(RegionSetWriter, SmallLimitSplitsIntoNestedRegionsThatRebuildTheSingleFile) {
    TempDir dir;
    const int w = 257;
    test::writeFloatRaster(dir.file("in.tif"), w, w, test::syntheticHeights(w, w, 2000.0f));
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 8;
    o.scale = 0.25;
    const DemReport single = encodeDem(dir.file("in.tif"), dir.file("one.dat"), o);
    ASSERT_EQ(single.header.maxLevel, 5); // 8 << 5 = 256
    const uint64_t cap = 8000;
    o.maxFileBytes = cap;
    const DemReport split = encodeDem(dir.file("in.tif"), dir.file("DEM.dat"), o);
    const Built set = readSet(dir.path(), "DEM.dat");
    EXPECT_EQ(set.index.at("format"), "libpyramid region set");
    EXPECT_EQ(set.index.at("kind"), "residual");
    EXPECT_EQ(set.index.at("main"), "DEM.dat");
    ASSERT_GT(set.regions.size(), 4u);
    ASSERT_EQ(split.files.size(), set.regions.size() + 1);

    // Every file within the limit; the report's sizes are the files'.
    uint64_t total = 0;
    for (const auto& [name, bytes] : split.files) {
        EXPECT_LE(std::filesystem::file_size(dir.file(name)), cap) << name;
        EXPECT_EQ(std::filesystem::file_size(dir.file(name)), bytes) << name;
        total += bytes;
    }
    EXPECT_EQ(split.bytes, total);

    // The main file: the top levels, from level 0; each region a valid region file: minLevel 0,
    // the main's tile size and scale, its root in its name and in the index, and nested ones
    // inside another region.
    const ResidualHeader mh = ResidualFileReader::open(dir.file("DEM.dat"))->header();
    EXPECT_EQ(mh.rootLevel, 0);
    EXPECT_EQ(mh.minLevel, single.header.minLevel);
    EXPECT_GE(mh.maxLevel, mh.minLevel - 1);
    EXPECT_LT(mh.maxLevel, single.header.maxLevel);
    bool nested = false;
    for (size_t k = 0; k < set.regions.size(); ++k) {
        const ResidualHeader rh = ResidualFileReader::open(set.regions[k])->header();
        const auto& root = set.index.at("regions")[k].at("root");
        EXPECT_EQ(rh.minLevel, 0);
        EXPECT_EQ(rh.tileSize, mh.tileSize);
        EXPECT_EQ(rh.scale, mh.scale);
        EXPECT_EQ(rh.rootLevel, root[0].get<int>());
        EXPECT_EQ(rh.rootTx, root[1].get<int>());
        EXPECT_EQ(rh.rootTy, root[2].get<int>());
        EXPECT_EQ(std::filesystem::path(set.regions[k]).filename().string(),
                  regionFilePath("DEM.dat", RegionRoot{rh.rootLevel, rh.rootTx, rh.rootTy}));
        EXPECT_LE(rh.rootLevel + rh.maxLevel, single.header.maxLevel);
        nested = nested || rh.rootLevel > mh.maxLevel + 1;
    }
    EXPECT_TRUE(nested) << "a limit this small nests regions";
    expectSameElevations(dir.file("one.dat"), dir.file("DEM.dat"), set.regions);
    // The set, opened by its main file, verifies against the source down to the finest level.
    const DemVerifyReport v = verifyDem(dir.file("DEM.dat"), dir.file("in.tif"), DemVerifyOptions{});
    EXPECT_TRUE(v.ok());
    ASSERT_EQ(v.levels.size(), static_cast<size_t>(single.header.maxLevel) + 1);
    EXPECT_EQ(v.levels.back().samples, 257 * 257);
    // The programs write the same set (the same bytes) with --max-file-bytes.
    const test::RunResult run = test::run(test::programPath("preprocessDem") + " -q " + dir.file("in.tif") + " -o " +
                                          dir.file("cli/DEM.dat") + " --tile-size 32 --root-tile-size 8 --scale 0.25 " +
                                          "--max-file-bytes 8000");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    for (const auto& [name, bytes] : split.files) {
        EXPECT_EQ(test::readFile(dir.file("cli/" + name)), test::readFile(dir.file(name))) << name;
    }
    EXPECT_EQ(test::readFile(dir.file("cli/DEM.dat.regions.json")), test::readFile(dir.file("DEM.dat.regions.json")));

    // The C API opens the set by its main file, its index or its directory: the single file's
    // elevations, at the finest level too.
    pyramid_elevation* one = nullptr;
    ASSERT_EQ(pyramid_elevation_open(dir.file("one.dat").c_str(), 0, 0, 8, &one), PYRAMID_OK);
    for (const std::string& path : {dir.file("DEM.dat"), dir.file("DEM.dat.regions.json"), dir.file("cli")}) {
        pyramid_elevation* opened = nullptr;
        ASSERT_EQ(pyramid_elevation_open(path.c_str(), 0, 0, 8, &opened), PYRAMID_OK) << path << ": " << pyramid_last_error();
        const int side = pyramid_elevation_side(opened);
        std::vector<float> a(static_cast<size_t>(side * side)), b(a.size());
        for (const auto& [level, tx, ty] : {std::tuple{0, 0, 0}, {2, 1, 3}, {3, 5, 6}}) {
            ASSERT_EQ(pyramid_elevation_tile(one, level, tx, ty, a.data(), nullptr, nullptr, a.size()), PYRAMID_OK);
            ASSERT_EQ(pyramid_elevation_tile(opened, level, tx, ty, b.data(), nullptr, nullptr, b.size()), PYRAMID_OK);
            EXPECT_EQ(a, b) << path << " tile " << level << "," << tx << "," << ty;
        }
        double za = 0.0, zb = 0.0;
        ASSERT_EQ(pyramid_elevation_height(one, -1, 0.3, 0.7, &za), PYRAMID_OK);
        ASSERT_EQ(pyramid_elevation_height(opened, -1, 0.3, 0.7, &zb), PYRAMID_OK);
        EXPECT_EQ(za, zb);
        pyramid_elevation_close(opened);
    }
    pyramid_elevation_close(one);
    // A set missing a region is refused, naming the file.
    std::filesystem::remove(dir.file("cli/") + split.files.back().first);
    pyramid_elevation* broken = nullptr;
    EXPECT_EQ(pyramid_elevation_open(dir.file("cli").c_str(), 0, 0, 8, &broken), PYRAMID_ERROR_FILE);
    EXPECT_NE(std::string(pyramid_last_error()).find(split.files.back().first), std::string::npos) << pyramid_last_error();
}

TEST(RegionSetWriter, APyramidThatFitsIsOneFileAndAnIndex) {
    TempDir dir;
    test::writeFloatRaster(dir.file("in.tif"), 65, 65, test::syntheticHeights(65, 65));
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 8;
    encodeDem(dir.file("in.tif"), dir.file("one.dat"), o);
    o.maxFileBytes = 0xFFFFFFFF;
    const DemReport r = encodeDem(dir.file("in.tif"), dir.file("DEM.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("DEM.dat")), test::readFile(dir.file("one.dat")));
    ASSERT_EQ(r.files.size(), 1u);
    EXPECT_TRUE(readSet(dir.path(), "DEM.dat").regions.empty());
}

TEST(RegionSetWriter, ALimitBelowTheTopLevelsIsRefusedAndLeavesNothing) {
    TempDir dir;
    test::writeFloatRaster(dir.file("in.tif"), 129, 129, test::syntheticHeights(129, 129));
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 8;
    o.maxFileBytes = 500;
    try {
        encodeDem(dir.file("in.tif"), dir.file("DEM.dat"), o);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("pass the file size limit of 500 bytes"), std::string::npos) << e.what();
    }
    for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
        EXPECT_EQ(entry.path().filename(), "in.tif");
    }
}

TEST(RegionSetWriter, SphericalFacesSplitEachIntoTheirOwnSet) {
    TempDir dir;
    const PlanetFunction planet([](double lat, double lon) { return 1000.0 * std::sin(lat / 7.0) * std::cos(lon / 11.0); },
                                512);
    SphericalDemOptions o;
    o.dem.tileSize = 32;
    o.dem.rootTileSize = 8;
    o.body = "sphere";
    o.faces = {2, 5};
    encodeSphericalDem(planet, dir.file("one"), o);
    o.dem.maxFileBytes = 6000;
    const SphericalDemReport r = encodeSphericalDem(planet, dir.file("set"), o);
    for (const int f : o.faces) {
        const std::string name = "DEM" + std::to_string(f) + ".dat";
        const Built set = readSet(dir.file("set"), name);
        ASSERT_FALSE(set.regions.empty());
        expectSameElevations(dir.file("one/" + name), dir.file("set/" + name), set.regions);
    }
    EXPECT_GT(r.faces[0].dem.files.size(), 1u);
    for (const auto& entry : std::filesystem::directory_iterator(dir.file("set"))) {
        EXPECT_NE(entry.path().filename().string().rfind(".staging", 0), 0u) << entry.path();
    }
}

} // namespace
} // namespace pyramid
