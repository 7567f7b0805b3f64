// The spherical commands as a user runs them: the sample maps (elevation and imagery), --height-scale as a ratio,
// --faces, --body, --extent, reports with ground sample distances, progress and --quiet, and
// the one-line errors of bad input with nothing left behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/ortho_file.hpp"
#include "formats/residual_file.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using test::programPath;
using test::run;

size_t lines(const std::string& s) { return static_cast<size_t>(std::count(s.begin(), s.end(), '\n')); }

size_t filesIn(const std::string& dir) {
    if (!std::filesystem::exists(dir)) {
        return 0;
    }
    size_t n = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
        n += e.is_regular_file();
    }
    return n;
}

struct BadCase {
    std::string args;
    int exitCode;
    std::string words; // the message must contain them
};

// Runs `program -q ARGS` for each case: the exit code, a one-line message naming the problem
// (for exit 1), and nothing written under `out`.
void expectBadInputWritesNothing(const std::string& program, const std::vector<BadCase>& cases,
                                 const std::string& out) {
    for (const BadCase& c : cases) {
        const auto r = run(programPath(program) + " -q " + c.args);
        EXPECT_EQ(r.exitCode, c.exitCode) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.words), std::string::npos) << c.args << "\n" << r.err;
        if (c.exitCode == 1) {
            EXPECT_EQ(lines(r.err), 1u) << r.err;
        }
        EXPECT_EQ(filesIn(out), 0u) << c.args;
        EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
    }
}

TEST(SphereDemCli, SampleMapMakesSixFacesAndAReport) {
    test::TempDir dir;
    const std::string out = dir.file("planet");
    const auto r = run(programPath("preprocessSphericalDem") + " " + test::samplePath("srtm.png") + " -o " + out +
                       " --tile-size 32 --root-tile-size 8 --height-scale 10000/255 --report " + dir.file("r.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("preprocessSphericalDem: 100%"), std::string::npos) << r.err;
    const nlohmann::json j = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_NEAR(j["input"]["height_scale"].get<double>(), 10000.0 / 255.0, 1e-12);
    EXPECT_NE(j["body"].get<std::string>().find("6378137"), std::string::npos);
    ASSERT_EQ(j["faces"].size(), 6u);
    for (int f = 1; f <= 6; ++f) {
        const nlohmann::json& face = j["faces"][static_cast<size_t>(f - 1)];
        EXPECT_EQ(face["face"], f);
        // 1350 / 4 = 337.5 intervals at the equator: 8 << 6 = 512 is the first level to reach it.
        EXPECT_EQ(face["dem"]["header"]["max_level"], 6);
        EXPECT_EQ(face["ground_sample_distance"].size(), 7u);
        const double finestMax = face["ground_sample_distance"][6]["max_metres"];
        EXPECT_GT(finestMax, 20e3); // about 10000 km / 512 at the face centre
        EXPECT_LT(finestMax, 30e3);
        for (const auto& level : face["dem"]["levels"]) {
            EXPECT_LE(level["max_error"].get<double>(), 0.5 + 1e-3);
        }
        const std::string file = out + "/DEM" + std::to_string(f) + ".dat";
        EXPECT_EQ(face["dem"]["output"], file);
        EXPECT_EQ(ResidualFileReader::open(file)->header().maxLevel, 6);
        const auto check = run(programPath("pyramid") + " check " + file);
        EXPECT_EQ(check.exitCode, 0) << check.out << check.err;
    }
    EXPECT_EQ(filesIn(out), 6u); // no staging leftovers

    // `pyramid verify DIR --source MAP`: every face rebuilt and compared with the map, sampled as
    // the encoder sampled it (the same --height-scale); the faces' own report said the same.
    const std::string verify = programPath("pyramid") + " verify -q " + out + " --source " + test::samplePath("srtm.png");
    auto v = run(verify + " --height-scale 10000/255 --json");
    ASSERT_EQ(v.exitCode, 0) << v.err << v.out;
    nlohmann::json vj = nlohmann::json::parse(v.out);
    EXPECT_EQ(vj["ok"], true);
    ASSERT_EQ(vj["faces"].size(), 6u);
    for (int f = 1; f <= 6; ++f) {
        const nlohmann::json& face = vj["faces"][static_cast<size_t>(f - 1)];
        EXPECT_EQ(face["face"], f);
        EXPECT_EQ(face["levels"].size(), 7u);
        for (size_t l = 0; l < 7; ++l) {
            EXPECT_NEAR(face["levels"][l]["max_error"].get<double>(),
                        j["faces"][static_cast<size_t>(f - 1)]["dem"]["levels"][l]["max_error"].get<double>(), 1e-3);
        }
    }
    v = run(verify + " --height-scale 10000/255 --faces 2 --json");
    ASSERT_EQ(v.exitCode, 0) << v.err;
    vj = nlohmann::json::parse(v.out);
    ASSERT_EQ(vj["faces"].size(), 1u);
    EXPECT_EQ(vj["faces"][0]["face"], 2);
    // Without the build's --height-scale the heights are 255/10000 of the faces': every face fails, in one line.
    v = run(verify);
    EXPECT_EQ(v.exitCode, 1);
    EXPECT_EQ(v.err, "pyramid: " + out + ": faces 1, 2, 3, 4, 5, 6 (DEMN.dat): samples beyond scale/2 or not finite "
                     "against " + test::samplePath("srtm.png") + "\n");
    EXPECT_NE(v.out.find("FAILED"), std::string::npos) << v.out;
}

TEST(SphereDemCli, FacesBodyExtentAndQuiet) {
    test::TempDir dir;
    const std::string out = dir.file("moon");
    const auto r = run("cd " + dir.path() + " && " + programPath("pyramid") + " sphere-dem " +
                       test::samplePath("srtm.png") + " -o moon --faces 1,6 --body moon --max-level 3 " +
                       "--extent -180,-90,180,90 -q --report -");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const nlohmann::json j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["faces"].size(), 2u);
    EXPECT_EQ(j["faces"][1]["face"], 6);
    // The Moon's radius is 1737.4 km: a face is about 2700 km across, 192 intervals at level 3.
    EXPECT_LT(j["faces"][0]["ground_sample_distance"][3]["max_metres"].get<double>(), 20e3);
    EXPECT_TRUE(std::filesystem::exists(out + "/DEM1.dat"));
    EXPECT_TRUE(std::filesystem::exists(out + "/DEM6.dat"));
    EXPECT_EQ(filesIn(out), 2u);
    // verify takes the faces the directory holds, on the body they were built on.
    const std::string verify = programPath("pyramid") + " verify -q " + out + " --source " +
                               test::samplePath("srtm.png") + " --extent -180,-90,180,90 --json";
    auto v = run(verify + " --body moon");
    ASSERT_EQ(v.exitCode, 0) << v.err;
    const nlohmann::json vj = nlohmann::json::parse(v.out);
    ASSERT_EQ(vj["faces"].size(), 2u);
    EXPECT_EQ(vj["faces"][1]["face"], 6);
    EXPECT_EQ(vj["faces"][1]["file"], out + "/DEM6.dat");
    // Sampled on another body, the map's heights land elsewhere.
    v = run(verify);
    EXPECT_EQ(v.exitCode, 1);
    EXPECT_EQ(nlohmann::json::parse(v.out)["ok"], false);
    // A face the directory does not hold, options that do not apply: one line, exit 1.
    for (const auto& [args, words] : std::vector<std::pair<std::string, std::string>>{
             {" --body moon --faces 2", "DEM2.dat"}, {" --body moon --stretch", "--stretch"},
             {" --body moon --crs EPSG:4326", "--crs"}}) {
        v = run(verify + args);
        EXPECT_EQ(v.exitCode, 1) << args;
        EXPECT_NE(v.err.find(words), std::string::npos) << args << "\n" << v.err;
        EXPECT_EQ(lines(v.err), 1u) << v.err;
    }
}

TEST(SphereDemCli, FillGivesTheHeightOfWhatTheMapDoesNotHold) {
    test::TempDir dir;
    // The sample map placed over the north-western quarter of the globe: the south pole's face
    // holds none of it.
    const std::string base = programPath("preprocessSphericalDem") + " " + test::samplePath("srtm.png") +
                             " --extent -180,0,0,90 --height-scale 10000/255 --faces 6 --max-level 3 -q --report - -o ";
    const std::string height = programPath("pyramid") + " height --lonlat 30,-70 ";
    auto r = run(base + dir.file("sea") + " --fill -12");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["fill"], -12.0);
    r = run(height + dir.file("sea"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.out, "-12\n");
    // By default the face takes the heights the map leads to across the cube: the sample map's
    // heights (1 to 6000 m), not 0 and not the given height.
    r = run(base + dir.file("smooth"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["fill"], "smooth");
    r = run(height + dir.file("smooth"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_GT(std::stod(r.out), 1.0) << r.out;
    EXPECT_LT(std::stod(r.out), 6000.0) << r.out;
}

TEST(SphereDemCli, BadInputIsOneLineAndWritesNothing) {
    test::TempDir dir;
    const std::string out = dir.file("out");
    const std::string srtm = test::samplePath("srtm.png");
    const std::vector<BadCase> cases = {
        {dir.file("missing.png") + " -o " + out, 1, "missing.png"},
        {srtm + " -o " + out + " --faces 0,1", 1, "--faces"},
        {srtm + " -o " + out + " --faces 1,1", 1, "--faces"},
        {srtm + " -o " + out + " --body pluto", 1, "--body"},
        {srtm + " -o " + out + " --extent 10,20,5,30", 1, "--extent"},
        {srtm + " -o " + out + " --height-scale 1/0", 1, "--height-scale"},
        {srtm + " -o " + out + " --height-scale x", 1, "--height-scale"},
        {srtm + " -o " + out + " --fill sea", 1, "--fill"},
        {srtm + " -o " + out + " --fill nan", 1, "--fill"},
        {srtm + " -o " + out + " --band 4", 1, "--band"},
        {srtm + " -o " + out + " --tile-size 8 --root-tile-size 1", 1, "--root-tile-size"},
        {srtm + " -o " + out + " --scale 0.001", 1, "overflow"}, // fails at the first face
        {srtm, 2, "--output"},
    };
    expectBadInputWritesNothing("preprocessSphericalDem", cases, out);
}

TEST(SphereDemCli, GeoTiffPlacesItselfAndRefusesWhatItCannot) {
    const std::string rainier = test::sharedFixturePath("inputs/mt_rainier_90m.tif");
    if (rainier.empty()) {
        GTEST_SKIP() << "../shared/fixtures/inputs/mt_rainier_90m.tif is not there";
    }
    test::TempDir dir;
    const std::string out = dir.file("planet");
    // The real SRTM tile without --extent: on face 1 (47 N), nowhere else.
    const auto r = run(programPath("preprocessSphericalDem") + " " + rainier + " -o " + out +
                       " --max-level 5 -q --report " + dir.file("r.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_EQ(j["crs"], "EPSG:4326 (WGS 84)");
    EXPECT_NEAR(j["extent"]["west"].get<double>(), -122.0 - 0.5 / 1200, 1e-9);
    EXPECT_NEAR(j["extent"]["north"].get<double>(), 47.0 + 0.5 / 1200, 1e-9);
    for (const nlohmann::json& face : j["faces"]) {
        EXPECT_EQ(face["dem"]["levels"].back()["samples"].get<int64_t>() > 0, face["face"] == 1) << face["face"];
    }

    const std::string laea = dir.file("laea.tif");
    test::writeGeoTiff(laea, 4, 4, std::vector<float>(16, 1.0f), test::projectedTags(3035, 4321000, 3210000, 1000));
    const std::string bad = dir.file("bad");
    const std::vector<BadCase> cases = {
        {rainier + " -o " + bad + " --extent -180,-90,180,90", 1,
         "preprocessSphericalDem: --extent: -180,-90,180,90 contradicts the file's georeferencing "
         "(-122.0004167,45.99958333,-120.9995833,47.00041667 in EPSG:4326 (WGS 84)); leave --extent out"},
        {laea + " -o " + bad, 1,
         "laea.tif: EPSG:3035 (ETRS89-extended / LAEA Europe) is in the Lambert azimuthal equal-area projection, "
         "which is not supported; reproject it to EPSG:4326"},
    };
    expectBadInputWritesNothing("preprocessSphericalDem", cases, bad);
    expectBadInputWritesNothing("preprocessSphericalOrtho", {{laea + " -o " + bad, 1, "EPSG:3035"}}, bad);
}

TEST(SphereDemCli, LayoutSparseWritesWhereTheMapIsAndDenseEveryTile) {
    test::TempDir dir;
    // 2 x 2 degrees near Mount Rainier at level 9 of 32-tiles: face 1 alone holds it.
    std::vector<float> heights(64 * 64);
    for (size_t k = 0; k < heights.size(); ++k) {
        heights[k] = 1000.0f + static_cast<float>(k % 64) * 13.0f - static_cast<float>(k / 64) * 7.0f;
    }
    const std::string map = dir.file("map.tif");
    test::writeGeoTiff(map, 64, 64, heights, test::geographicTags(4326, -122.5, 47.5, 2.0 / 64));
    const std::string cmd = programPath("preprocessSphericalDem") + " " + map +
                            " --tile-size 32 --root-tile-size 4 --max-level 9 --scale 0.25 -q -o ";
    const auto sparse = run(cmd + dir.file("sparse") + " --report " + dir.file("sparse.json"));
    ASSERT_EQ(sparse.exitCode, 0) << sparse.err;
    const auto dense = run(cmd + dir.file("dense") + " --layout dense --report " + dir.file("dense.json"));
    ASSERT_EQ(dense.exitCode, 0) << dense.err;
    const nlohmann::json s = nlohmann::json::parse(test::readFile(dir.file("sparse.json")));
    const nlohmann::json d = nlohmann::json::parse(test::readFile(dir.file("dense.json")));
    for (int face = 1; face <= 6; ++face) {
        const std::string name = "/DEM" + std::to_string(face) + ".dat";
        // Sparse: every face a set with its index; a face the map does not reach, its top levels.
        EXPECT_TRUE(std::filesystem::exists(dir.file("sparse") + name + ".regions.json")) << face;
        EXPECT_FALSE(std::filesystem::exists(dir.file("dense") + name + ".regions.json")) << face;
        EXPECT_EQ(ResidualFileReader::readHeader(dir.file("dense") + name).maxLevel, 9) << face;
        const nlohmann::json& sf = s["faces"][face - 1]["dem"];
        const nlohmann::json& df = d["faces"][face - 1]["dem"];
        EXPECT_LT(sf["bytes"].get<uint64_t>() * (face == 1 ? 2 : 20), df["bytes"].get<uint64_t>()) << face;
        if (face != 1) {
            EXPECT_EQ(ResidualFileReader::readHeader(dir.file("sparse") + name).maxLevel, 3) << face;
            EXPECT_EQ(sf["tiles"].get<int64_t>(), 4) << face;
        }
    }
    expectBadInputWritesNothing("preprocessSphericalDem",
                                {{map + " -o " + dir.file("bad") + " --layout thin", 2, "--layout"}}, dir.file("bad"));
}

// preprocessSphericalOrtho --layout: sparse (the default) writes each output of a face the map
// does not fill as a set of the files that hold the map; dense, every tile in one file.
TEST(SphereOrthoCli, LayoutSparseWritesWhereTheMapIsAndDenseEveryTile) {
    test::TempDir dir;
    std::vector<uint8_t> rgb(48 * 48 * 3);
    for (size_t k = 0; k < rgb.size(); ++k) {
        rgb[k] = static_cast<uint8_t>(30 + (k * 7) % 200);
    }
    const std::string map = dir.file("map.tif");
    test::writeGeoTiffRgb(map, 48, 48, rgb, test::geographicTags(4326, -122.5, 47.5, 1.0 / 48));
    const std::string cmd = programPath("preprocessSphericalOrtho") + " " + map +
                            " --tile-size 32 --max-level 8 --faces 1,2 -q -o ";
    ASSERT_EQ(run(cmd + dir.file("sparse")).exitCode, 0);
    ASSERT_EQ(run(cmd + dir.file("dense") + " --layout dense").exitCode, 0);
    for (const std::string sub : {"", "dxt/", "residuals/"}) {
        for (const int face : {1, 2}) {
            const std::string name = sub + "RGB" + std::to_string(face) + ".dat";
            EXPECT_TRUE(std::filesystem::exists(dir.file("sparse/" + name + ".regions.json"))) << name;
            EXPECT_FALSE(std::filesystem::exists(dir.file("dense/" + name + ".regions.json"))) << name;
            EXPECT_EQ(OrthoFileReader::open(dir.file("dense/" + name))->header().maxLevel, 8) << name;
            EXPECT_LT(std::filesystem::file_size(dir.file("sparse/" + name)) * 4,
                      std::filesystem::file_size(dir.file("dense/" + name)))
                << name;
        }
    }
    expectBadInputWritesNothing("preprocessSphericalOrtho",
                                {{map + " -o " + dir.file("bad") + " --layout thin", 2, "--layout"}}, dir.file("bad"));
}

TEST(SphereOrthoCli, SampleImageMakesEighteenFilesAndAReport) {
    test::TempDir dir;
    const std::string out = dir.file("planet");
    const auto r = run(programPath("pyramid") + " sphere-ortho " + test::samplePath("bluemarble.png") + " -o " + out +
                       " --tile-size 64 --faces 1,2,3,4,5,6 --report " + dir.file("r.json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("preprocessSphericalOrtho: 100%"), std::string::npos) << r.err;
    const nlohmann::json j = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    ASSERT_EQ(j["faces"].size(), 6u);
    for (int f = 1; f <= 6; ++f) {
        const nlohmann::json& face = j["faces"][static_cast<size_t>(f - 1)];
        EXPECT_EQ(face["face"], f);
        // 1350 / 4 = 337.5 pixels at the equator: 64 << 3 = 512 is the first level to reach it.
        EXPECT_EQ(face["ortho"]["max_level"], 3);
        EXPECT_EQ(face["ground_sample_distance"].size(), 4u);
        for (const char* file : {"/RGB", "/dxt/RGB", "/residuals/RGB"}) {
            const std::string path = out + file + std::to_string(f) + ".dat";
            const auto check = run(programPath("pyramid") + " check " + path);
            EXPECT_EQ(check.exitCode, 0) << path << check.out << check.err;
        }
    }
    EXPECT_EQ(filesIn(out), 18u);

    // `pyramid verify DIR --source MAP` on each of the three folders: the plain tiles equal the
    // map's, sampled as the encoder sampled it; DXT tiles are lossy (reported); the colour
    // residuals rebuild the colours within 1.
    const std::string map = test::samplePath("bluemarble.png");
    const auto verify = [&](const std::string& folder, const std::string& args) {
        return run(programPath("pyramid") + " verify -q " + folder + " --source " + map + args);
    };
    auto v = verify(out, " --json");
    ASSERT_EQ(v.exitCode, 0) << v.err;
    nlohmann::json vj = nlohmann::json::parse(v.out);
    ASSERT_EQ(vj["faces"].size(), 6u);
    for (int f = 1; f <= 6; ++f) {
        const nlohmann::json& face = vj["faces"][static_cast<size_t>(f - 1)];
        EXPECT_EQ(face["face"], f);
        EXPECT_EQ(face["file"], out + "/RGB" + std::to_string(f) + ".dat");
        EXPECT_EQ(face["mode"], "tiles");
        ASSERT_EQ(face["levels"].size(), 4u);
        for (const auto& level : face["levels"]) {
            EXPECT_EQ(level["max_error"], 0);
        }
    }
    v = verify(out + "/dxt", " --json");
    ASSERT_EQ(v.exitCode, 0) << v.err;
    vj = nlohmann::json::parse(v.out);
    EXPECT_EQ(vj["faces"][0]["mode"], "dxt");
    EXPECT_GT(vj["faces"][0]["levels"][3]["lossy_tiles"].get<int64_t>(), 0);
    v = verify(out + "/residuals", " --colour-residuals --faces 3 --json");
    ASSERT_EQ(v.exitCode, 0) << v.err;
    vj = nlohmann::json::parse(v.out);
    ASSERT_EQ(vj["faces"].size(), 1u);
    EXPECT_EQ(vj["faces"][0]["face"], 3);
    for (const auto& level : vj["faces"][0]["levels"]) {
        EXPECT_LE(level["max_error"].get<int>(), 1);
    }
    // Residuals compared as tiles, another map, options of DEM faces: one line, exit 1.
    v = verify(out + "/residuals", "");
    EXPECT_EQ(v.exitCode, 1);
    EXPECT_NE(v.err.find("(its folder is residuals/: verify colour residuals with --colour-residuals)"),
              std::string::npos)
        << v.err;
    v = run(programPath("pyramid") + " verify -q " + out + " --source " + test::samplePath("srtm.png"));
    EXPECT_EQ(v.exitCode, 1);
    EXPECT_EQ(v.err, "pyramid: " + out + ": faces 1, 2, 3, 4, 5, 6 (RGBN.dat): lossless tiles differ against " +
                         test::samplePath("srtm.png") + "\n");
    // --name names the faces: this directory holds no DEM faces, so it is not taken as a planet's.
    v = verify(out, " --name DEM");
    EXPECT_EQ(v.exitCode, 1);
    EXPECT_EQ(v.out, "");
    v = verify(out, " --height-scale 2");
    EXPECT_EQ(v.exitCode, 1);
    EXPECT_NE(v.err.find("--height-scale: does not apply to a planet's imagery faces"), std::string::npos) << v.err;
}

TEST(SphereOrthoCli, BadInputIsOneLineAndWritesNothing) {
    test::TempDir dir;
    const std::string out = dir.file("out");
    const std::string image = test::samplePath("bluemarble.png");
    const std::vector<BadCase> cases = {
        {dir.file("missing.png") + " -o " + out, 1, "missing.png"},
        {test::samplePath("dem.tif") + " -o " + out, 1, "dem.tif"}, // float heights are no imagery
        {image + " -o " + out + " --faces 7", 1, "--faces"},
        {image + " -o " + out + " --body 0,0", 1, "--body"},
        {image + " -o " + out + " --outputs tiff,png", 1, "--outputs"},
        {image + " -o " + out + " --max-level 21", 1, "--max-level"},
        {image, 2, "--output"},
    };
    expectBadInputWritesNothing("preprocessSphericalOrtho", cases, out);
}

// 8-bit RGB, 1024 x 512 pixels in tiles of 512 x 512 (0.75 MB decoded each), placed by `tags`.
std::string writeTiledRgb(const test::TempDir& dir, const std::string& name, test::GeoTiffTags tags) {
    std::vector<uint8_t> rgb(1024 * 512 * 3);
    for (size_t k = 0; k < rgb.size(); ++k) {
        rgb[k] = static_cast<uint8_t>((k * 7 + k / 3000) % 250 + 3);
    }
    tags.tileSize = 512;
    const std::string path = dir.file(name);
    test::writeGeoTiffRgb(path, 1024, 512, rgb, tags);
    return path;
}

// A map in large tiles is read with the cache it needs (not refused for a probe's cache); a map in
// a projection no GeoKey can say (GDAL's geostationary satellite view: a user-defined model with
// its ESRI string in the citation) is refused in one line naming the file and the projection.
TEST(SphereOrthoCli, LargeTilesAreReadAndAnUnplaceableProjectionIsNamed) {
    test::TempDir dir;
    const std::string global = writeTiledRgb(dir, "global.tif", test::geographicTags(4326, -180.0, 90.0, 360.0 / 1024));
    const test::RunResult ok = run(programPath("preprocessSphericalOrtho") + " " + global + " -o " + dir.file("ok") +
                                   " --tile-size 32 --max-level 2 --outputs tiff -q");
    EXPECT_EQ(ok.exitCode, 0) << ok.err;
    EXPECT_TRUE(std::filesystem::exists(dir.file("ok/RGB1.dat")));

    test::GeoTiffTags geos;
    geos.shortKeys = {{1024, 32767}, {1025, 1}}; // GTModelTypeGeoKey user-defined, PixelIsArea
    geos.asciiKeys = {{1026, "unknown|ESRI PE String = PROJCS[\"unknown\",GEOGCS[\"GCS_unknown\",DATUM["
                             "\"D_WGS_1984\",SPHEROID[\"WGS_1984\",6378137.0,298.257223563]],PRIMEM[\"Greenwich\",0.0],"
                             "UNIT[\"Degree\",0.0174532925199433]],PROJECTION[\"Geostationary_Satellite\"],"
                             "PARAMETER[\"Height\",35785831.0],UNIT[\"Meter\",1.0]]|"}};
    geos.tiepoints = {0.0, 0.0, 0.0, -5500000.0, 5500000.0, 0.0};
    geos.pixelScale = {10742.0, 10742.0, 0.0};
    const std::string satellite = writeTiledRgb(dir, "geos.tif", geos);
    const test::RunResult refused =
        run(programPath("preprocessSphericalOrtho") + " " + satellite + " -o " + dir.file("geos") + " -q");
    EXPECT_EQ(refused.exitCode, 1);
    EXPECT_NE(refused.err.find("geos.tif"), std::string::npos) << refused.err;
    EXPECT_NE(refused.err.find("Geostationary_Satellite"), std::string::npos) << refused.err;
    EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("geos")));
}


} // namespace
} // namespace pyramid
