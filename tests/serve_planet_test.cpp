// `pyramid serve` over a planet: six faces, their frames (sphere/cube_faces.hpp) and radius in
// pyramid.json, every elevation and ortho tile of every face bit for bit as the C API makes it
// (ortho as stored and rebuilt from colour residuals), and 404 for the tiles a sparse planet does
// not hold.
#include <gtest/gtest.h>
#include <httplib.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/capi/pyramid.h"
#include "libpyramid/runtime/pyramid_set_producers.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "support/paths.hpp"
#include "support/served_program.hpp"

namespace {

using pyramid::test::decodePng;
using pyramid::test::ServedProgram;

std::string tileUrl(int face, const std::string& kind, int level, int tx, int ty, const std::string& format) {
    return "/tiles/" + std::to_string(face) + "/" + kind + "/" + std::to_string(level) + "/" + std::to_string(tx) +
           "/" + std::to_string(ty) + "." + format;
}

class ServePlanet : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir = new pyramid::test::TempDir();
        planet = dir->file("planet");
        const auto dem = pyramid::test::run(pyramid::test::programPath("preprocessSphericalDem") + " -q " +
                                            pyramid::test::samplePath("srtm.png") + " -o " + planet +
                                            " --tile-size 32 --root-tile-size 8 --max-level 4 --threads 2");
        ASSERT_EQ(dem.exitCode, 0) << dem.err;
        const auto ortho = pyramid::test::run(pyramid::test::programPath("preprocessSphericalOrtho") + " -q " +
                                              pyramid::test::samplePath("bluemarble.png") + " -o " + planet +
                                              " --tile-size 32 --max-level 2 --threads 2");
        ASSERT_EQ(ortho.exitCode, 0) << ortho.err;
    }
    static void TearDownTestSuite() {
        delete dir;
        dir = nullptr;
    }
    static pyramid::test::TempDir* dir;
    static std::string planet;
};
pyramid::test::TempDir* ServePlanet::dir = nullptr;
std::string ServePlanet::planet;

void expectFaceElevations(httplib::Client& client, const std::string& file, int face, int maxLevel) {
    pyramid_elevation* e = nullptr;
    ASSERT_EQ(pyramid_elevation_open(file.c_str(), 0, 0, 16, &e), PYRAMID_OK) << pyramid_last_error();
    const int side = pyramid_elevation_side(e);
    std::vector<float> zf(static_cast<size_t>(side * side));
    for (int level = 0; level <= maxLevel; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                ASSERT_EQ(pyramid_elevation_tile(e, level, tx, ty, zf.data(), nullptr, nullptr, zf.size()), PYRAMID_OK);
                const std::string expected(reinterpret_cast<const char*>(zf.data()), zf.size() * 4);
                const auto raw = client.Get(tileUrl(face, "elevation", level, tx, ty, "f32"));
                ASSERT_TRUE(raw);
                ASSERT_EQ(raw->status, 200) << raw->body;
                EXPECT_TRUE(raw->body == expected) << "face " << face << " tile " << level << "," << tx << "," << ty;
                const auto png = client.Get(tileUrl(face, "elevation", level, tx, ty, "png"));
                ASSERT_TRUE(png);
                const auto image = decodePng(png->body);
                ASSERT_EQ(image.width, side);
                ASSERT_EQ(image.channels, 4);
                EXPECT_EQ(std::memcmp(image.pixels.data(), expected.data(), expected.size()), 0);
            }
        }
    }
    pyramid_elevation_close(e);
}

void expectFaceOrthos(httplib::Client& client, const std::string& file, int colourResiduals, int face, int maxLevel) {
    pyramid_ortho* o = nullptr;
    ASSERT_EQ(pyramid_ortho_open(file.c_str(), colourResiduals, 16, &o), PYRAMID_OK) << pyramid_last_error();
    int side = 0, channels = 0;
    ASSERT_EQ(pyramid_ortho_layout(o, &side, &channels), PYRAMID_OK);
    std::vector<unsigned char> pixels(static_cast<size_t>(side * side * channels));
    for (int level = 0; level <= maxLevel; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                ASSERT_EQ(pyramid_ortho_tile(o, level, tx, ty, pixels.data(), pixels.size()), PYRAMID_OK);
                const auto png = client.Get(tileUrl(face, "ortho", level, tx, ty, "png"));
                ASSERT_TRUE(png);
                ASSERT_EQ(png->status, 200) << png->body;
                EXPECT_EQ(pyramid::test::orthoPngMismatch(png->body, pixels, side, channels), "")
                    << "face " << face << " ortho " << level << "," << tx << "," << ty;
            }
        }
    }
    pyramid_ortho_close(o);
}

TEST_F(ServePlanet, SixFacesWithTheirFramesAndEveryTileAsTheCApiMakesIt) {
    ServedProgram served({planet, "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    httplib::Client client(served.host(), served.port());
    const auto answer = client.Get("/api/pyramid.json");
    ASSERT_TRUE(answer);
    const nlohmann::json j = nlohmann::json::parse(answer->body);
    EXPECT_EQ(j.at("kind"), "planet");
    EXPECT_EQ(j.at("radius"), 6378137.0); // --body wgs84, the default
    ASSERT_EQ(j.at("faces").size(), 6u);
    for (int f = 1; f <= 6; ++f) {
        const nlohmann::json& face = j.at("faces")[static_cast<size_t>(f - 1)];
        EXPECT_EQ(face.at("face"), f);
        // frame (u, v, 1) is faceDirection(f, u, v).
        const nlohmann::json& m = face.at("frame");
        for (const auto& [u, v] : {std::pair{0.3, -0.7}, std::pair{-1.0, 1.0}, std::pair{0.0, 0.0}}) {
            const auto d = pyramid::faceDirection(f, u, v);
            for (size_t r = 0; r < 3; ++r) {
                EXPECT_DOUBLE_EQ(m[r][0].get<double>() * u + m[r][1].get<double>() * v + m[r][2].get<double>(), d[r]);
            }
        }
        const int maxLevel = face.at("elevation").at("max_level").get<int>();
        EXPECT_GE(maxLevel, 1);
        EXPECT_EQ(face.at("elevation").at("side"), 37);
        EXPECT_EQ(face.at("elevation").at("file"), pyramid::faceFileName("DEM", f));
        expectFaceElevations(client, pyramid::faceFilePath(planet, "DEM", f), f, maxLevel);
        ASSERT_TRUE(face.at("ortho").is_object());
        EXPECT_EQ(face.at("ortho").at("file"), pyramid::faceFileName("RGB", f));
        expectFaceOrthos(client, pyramid::faceFilePath(planet, "RGB", f), 0, f, face.at("ortho").at("max_level"));
    }
    // Face 1 is (u, v, 1); face 3 is (1, u, v).
    EXPECT_EQ(j.at("faces")[0].at("frame"), nlohmann::json::parse("[[1,0,0],[0,1,0],[0,0,1]]"));
    EXPECT_EQ(j.at("faces")[2].at("frame"), nlohmann::json::parse("[[0,0,1],[1,0,0],[0,1,0]]"));
}

TEST_F(ServePlanet, TheOptionsSayWhichFacesOnWhichBodyAndServeTheSameTiles) {
    // Faces under another name (--name), another body's radius (--body), one serving thread and
    // a one-tile cache: the same tiles.
    const std::string renamed = dir->file("renamed");
    std::filesystem::create_directories(renamed);
    for (int f = 1; f <= 6; ++f) {
        std::filesystem::copy_file(pyramid::faceFilePath(planet, "DEM", f), pyramid::faceFilePath(renamed, "HGT", f));
    }
    ServedProgram served({renamed, "--name", "HGT", "--body", "moon", "--threads", "1", "--cache-tiles", "1",
                          "--bind", "127.0.0.1", "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    httplib::Client client(served.host(), served.port());
    const nlohmann::json j = nlohmann::json::parse(client.Get("/api/pyramid.json")->body);
    EXPECT_EQ(j.at("radius"), 1737400.0);
    ASSERT_EQ(j.at("faces").size(), 6u);
    EXPECT_EQ(j.at("faces")[4].at("elevation").at("file"), pyramid::faceFileName("HGT", 5));
    expectFaceElevations(client, pyramid::faceFilePath(renamed, "HGT", 5), 5,
                         j.at("faces")[4].at("elevation").at("max_level"));
    // The default name finds nothing there: one line naming the directory.
    const auto none = pyramid::test::run(pyramid::test::programPath("pyramid") + " serve " + renamed + " --port 0");
    EXPECT_EQ(none.exitCode, 1);
    EXPECT_NE(none.err.find(renamed), std::string::npos) << none.err;
    EXPECT_EQ(std::count(none.err.begin(), none.err.end(), '\n'), 1) << none.err;
}

TEST_F(ServePlanet, ColourResidualFacesAreRebuiltAsTheCApiRebuildsThem) {
    ServedProgram served({planet, "--ortho", planet + "/residuals", "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    httplib::Client client(served.host(), served.port());
    const nlohmann::json j = nlohmann::json::parse(client.Get("/api/pyramid.json")->body);
    for (const int f : {1, 4}) {
        const nlohmann::json& ortho = j.at("faces")[static_cast<size_t>(f - 1)].at("ortho");
        EXPECT_EQ(ortho.at("colour_residuals"), true);
        expectFaceOrthos(client, pyramid::faceFilePath(planet + "/residuals", "RGB", f), 1, f, ortho.at("max_level"));
    }
}

TEST_F(ServePlanet, TilesASparsePlanetDoesNotHoldAre404) {
    const std::string sparse = dir->file("sparse");
    const auto built = pyramid::test::run(pyramid::test::programPath("preprocessSphericalDem") + " -q " +
                                          pyramid::test::samplePath("srtm.png") + " -o " + sparse +
                                          " --extent 10,10,12,12 --faces 3 --tile-size 32 --root-tile-size 4 --max-level 9 --threads 2");
    ASSERT_EQ(built.exitCode, 0) << built.err;
    ServedProgram served({sparse, "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    httplib::Client client(served.host(), served.port());
    const nlohmann::json j = nlohmann::json::parse(client.Get("/api/pyramid.json")->body);
    ASSERT_EQ(j.at("faces").size(), 1u);
    const int maxLevel = j.at("faces")[0].at("elevation").at("max_level");
    const auto producer = pyramid::openElevationSet(pyramid::faceFilePath(sparse, "DEM", 3));
    ASSERT_TRUE(std::filesystem::exists(pyramid::faceFilePath(sparse, "DEM", 3) + ".regions.json")); // a sparse set
    // Every tile the set holds at the deepest level, and every 997th of the others.
    int absent = 0, present = 0, others = 0;
    for (int ty = 0; ty < (1 << maxLevel); ++ty) {
        for (int tx = 0; tx < (1 << maxLevel); ++tx) {
            const bool held = producer->hasResiduals(maxLevel, tx, ty);
            if (!held && others++ % 997 != 0) {
                continue;
            }
            const auto tile = client.Get(tileUrl(3, "elevation", maxLevel, tx, ty, "f32"));
            ASSERT_TRUE(tile);
            EXPECT_EQ(tile->status, held ? 200 : 404) << tx << "," << ty;
            (held ? present : absent) += 1;
        }
    }
    EXPECT_GT(absent, 0);
    EXPECT_GT(present, 0);
}

} // namespace
