// `pyramid serve` answers tiles bit for bit as the C API makes them: every elevation tile of a
// plane's levels as float32 and as RGBA PNG, and every ortho tile, against pyramid_elevation_tile
// and pyramid_ortho_tile (a planet's faces: serve_planet_test.cpp).
#include <gtest/gtest.h>
#include <httplib.h>

#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/capi/pyramid.h"
#include "support/paths.hpp"
#include "support/served_program.hpp"

namespace {

using pyramid::test::decodePng;
using pyramid::test::ServedProgram;

std::string tileUrl(int face, const std::string& kind, int level, int tx, int ty, const std::string& format) {
    return "/tiles/" + std::to_string(face) + "/" + kind + "/" + std::to_string(level) + "/" + std::to_string(tx) +
           "/" + std::to_string(ty) + "." + format;
}

// Every elevation tile of levels 0..maxLevel of `face`, as .f32 and .png, against the C API's zf.
void expectElevationTiles(httplib::Client& client, const std::string& file, int face, int maxLevel) {
    pyramid_elevation* e = nullptr;
    ASSERT_EQ(pyramid_elevation_open(file.c_str(), 0, 0, 16, &e), PYRAMID_OK) << pyramid_last_error();
    const int side = pyramid_elevation_side(e);
    std::vector<float> zf(static_cast<size_t>(side * side));
    int tiles = 0;
    for (int level = 0; level <= maxLevel; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                ASSERT_EQ(pyramid_elevation_tile(e, level, tx, ty, zf.data(), nullptr, nullptr, zf.size()), PYRAMID_OK);
                const std::string expected(reinterpret_cast<const char*>(zf.data()), zf.size() * 4);
                const auto raw = client.Get(tileUrl(face, "elevation", level, tx, ty, "f32"));
                ASSERT_TRUE(raw) << "no answer";
                ASSERT_EQ(raw->status, 200) << raw->body;
                EXPECT_EQ(raw->get_header_value("Content-Type"), "application/octet-stream");
                EXPECT_EQ(raw->get_header_value("X-Pyramid-Side"), std::to_string(side));
                ASSERT_EQ(raw->body.size(), expected.size());
                EXPECT_TRUE(raw->body == expected) << "face " << face << " tile " << level << "," << tx << "," << ty;
                const auto png = client.Get(tileUrl(face, "elevation", level, tx, ty, "png"));
                ASSERT_TRUE(png);
                ASSERT_EQ(png->status, 200) << png->body;
                EXPECT_EQ(png->get_header_value("Content-Type"), "image/png");
                const auto image = decodePng(png->body);
                ASSERT_EQ(image.width, side);
                ASSERT_EQ(image.height, side);
                ASSERT_EQ(image.channels, 4);
                EXPECT_EQ(std::memcmp(image.pixels.data(), expected.data(), expected.size()), 0)
                    << "face " << face << " PNG tile " << level << "," << tx << "," << ty;
                ++tiles;
            }
        }
    }
    EXPECT_GT(tiles, 1);
    pyramid_elevation_close(e);
}

// Every ortho tile of levels 0..maxLevel of `face` as PNG, against the C API's.
void expectOrthoTiles(httplib::Client& client, const std::string& file, int colourResiduals, int face, int maxLevel) {
    pyramid_ortho* o = nullptr;
    ASSERT_EQ(pyramid_ortho_open(file.c_str(), colourResiduals, 16, &o), PYRAMID_OK) << pyramid_last_error();
    int side = 0, channels = 0;
    ASSERT_EQ(pyramid_ortho_layout(o, &side, &channels), PYRAMID_OK);
    std::vector<unsigned char> pixels(static_cast<size_t>(side * side * channels));
    int tiles = 0;
    for (int level = 0; level <= maxLevel; ++level) {
        for (int ty = 0; ty < (1 << level); ++ty) {
            for (int tx = 0; tx < (1 << level); ++tx) {
                const auto png = client.Get(tileUrl(face, "ortho", level, tx, ty, "png"));
                ASSERT_TRUE(png);
                const pyramid_status s = pyramid_ortho_tile(o, level, tx, ty, pixels.data(), pixels.size());
                if (s == PYRAMID_ERROR_NOT_FOUND) {
                    EXPECT_EQ(png->status, 404);
                    continue;
                }
                ASSERT_EQ(s, PYRAMID_OK);
                ASSERT_EQ(png->status, 200) << png->body;
                EXPECT_EQ(png->get_header_value("X-Pyramid-Side"), std::to_string(side));
                EXPECT_EQ(pyramid::test::orthoPngMismatch(png->body, pixels, side, channels), "")
                    << "face " << face << " ortho tile " << level << "," << tx << "," << ty;
                ++tiles;
            }
        }
    }
    EXPECT_GT(tiles, 0);
    pyramid_ortho_close(o);
}

TEST(ServeTiles, APlaneWithItsOrthoIsServedAsTheCApiMakesIt) {
    const std::string dem = pyramid::test::dataPath("proland/DEM.dat");
    ServedProgram served({dem, "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    httplib::Client client(served.host(), served.port());
    const auto answer = client.Get("/api/pyramid.json");
    ASSERT_TRUE(answer);
    ASSERT_EQ(answer->status, 200);
    const nlohmann::json j = nlohmann::json::parse(answer->body);
    EXPECT_EQ(j.at("format"), "libpyramid-serve 1");
    EXPECT_EQ(j.at("kind"), "plane");
    EXPECT_EQ(j.at("name"), "DEM.dat");
    EXPECT_TRUE(j.at("radius").is_null());
    EXPECT_TRUE(j.at("extent").is_null()); // no georeference sidecar
    EXPECT_EQ(j.at("tiles").at("elevation"), "/tiles/{face}/elevation/{level}/{tx}/{ty}.f32");
    EXPECT_EQ(j.at("tiles").at("ortho"), "/tiles/{face}/ortho/{level}/{tx}/{ty}.png");
    ASSERT_EQ(j.at("faces").size(), 1u);
    const nlohmann::json& face = j.at("faces")[0];
    EXPECT_EQ(face.at("face"), 0);
    EXPECT_TRUE(face.at("frame").is_null());
    const nlohmann::json& e = face.at("elevation");
    // DEM.dat: tile size 192, levels 0..5 with minLevel 3: elevation tiles of 192 intervals at
    // producer levels 0..2.
    EXPECT_EQ(e.at("tile_size"), 192);
    EXPECT_EQ(e.at("grid"), 192);
    EXPECT_EQ(e.at("side"), 197);
    EXPECT_EQ(e.at("border"), 2);
    EXPECT_EQ(e.at("max_level"), 2);
    EXPECT_EQ(e.at("min_level"), 0);
    EXPECT_EQ(e.at("file_min_level"), 3);
    EXPECT_EQ(e.at("file_max_level"), 5);
    EXPECT_FLOAT_EQ(e.at("scale").get<float>(), 0.1f);
    EXPECT_EQ(e.at("file"), "DEM.dat");
    const nlohmann::json& o = face.at("ortho");
    ASSERT_TRUE(o.is_object());
    EXPECT_EQ(o.at("max_level"), 1);
    EXPECT_EQ(o.at("tile_size"), 192);
    EXPECT_EQ(o.at("side"), 196);
    EXPECT_EQ(o.at("border"), 2);
    EXPECT_EQ(o.at("channels"), 4);
    EXPECT_EQ(o.at("file"), "RGB.dat");
    expectElevationTiles(client, dem, 0, e.at("max_level").get<int>());
    expectOrthoTiles(client, pyramid::test::dataPath("proland/RGB.dat"), 0, 0, o.at("max_level").get<int>());
}

TEST(ServeTiles, AnOrthoGivenWithOrthoIsServedAndNoneMeansNull) {
    pyramid::test::TempDir dir;
    const std::string dem = dir.file("DEM.dat");
    ASSERT_EQ(pyramid::test::run("cp " + pyramid::test::dataPath("proland/DEM.dat") + " " + dem).exitCode, 0);
    {
        ServedProgram alone({dem, "--port", "0", "-q"});
        ASSERT_TRUE(alone.ok()) << alone.error();
        httplib::Client client(alone.host(), alone.port());
        const auto answer = client.Get("/api/pyramid.json");
        ASSERT_TRUE(answer);
        EXPECT_TRUE(nlohmann::json::parse(answer->body).at("faces")[0].at("ortho").is_null());
        const auto tile = client.Get("/tiles/0/ortho/0/0/0.png");
        ASSERT_TRUE(tile);
        EXPECT_EQ(tile->status, 404);
    }
    const std::string rgb = pyramid::test::dataPath("proland/RGB.dat");
    ServedProgram served({dem, "--ortho", rgb, "--port", "0", "-q"});
    ASSERT_TRUE(served.ok()) << served.error();
    httplib::Client client(served.host(), served.port());
    expectOrthoTiles(client, rgb, 0, 0, 1);
}

TEST(ServeTiles, PathsThatAreNoBuildFailWithOneLine) {
    pyramid::test::TempDir dir;
    const std::string program = pyramid::test::programPath("pyramid");
    const auto missing = pyramid::test::run(program + " serve " + dir.file("none.dat") + " --port 0");
    EXPECT_EQ(missing.exitCode, 1);
    EXPECT_EQ(missing.err, "pyramid: " + dir.file("none.dat") + ": no such file or directory\n");
    const auto empty = pyramid::test::run(program + " serve " + dir.path() + " --port 0");
    EXPECT_EQ(empty.exitCode, 1);
    EXPECT_NE(empty.err.find(dir.path() + ": not a build"), std::string::npos) << empty.err;
    const auto ortho = pyramid::test::run(program + " serve " + pyramid::test::dataPath("proland/RGB.dat") + " --port 0");
    EXPECT_EQ(ortho.exitCode, 1);
    EXPECT_NE(ortho.err.find("an ortho pyramid, not a DEM"), std::string::npos) << ortho.err;
}

} // namespace
