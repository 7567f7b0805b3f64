// preprocessOrtho as a user runs it: a build checked and verified, failing cleanly; tiles fitted
// to the input (--tile-size auto); the residual
// Deflate level reaching the encoder; tiles beyond the cache naming its flag; the report's JPEG
// error as `pyramid verify` measures it; YCbCr JPEG tiles warned of and verified.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "formats/ortho_file.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::shellQuoted;

TEST(PreprocessOrthoCli, BuildsVerifiesAndFailsCleanly) {
    test::TempDir dir;
    std::vector<uint16_t> px(48 * 40 * 3);
    for (size_t k = 0; k < px.size(); ++k) {
        px[k] = static_cast<uint16_t>((k * 37) % 251);
    }
    test::writeImage(dir.file("in.png"), 48, 40, 3, px, false);
    auto r = test::run(test::programPath("preprocessOrtho") + " '" + dir.file("in.png") + "' -o '" + dir.file("out") +
                       "' --tile-size 16 --quiet --report '" + dir.file("r.json") + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto report = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_EQ(report["outputs"].size(), 3u);
    EXPECT_EQ(report["max_level"], 2);
    for (const char* f : {"/out/RGB.dat", "/out/dxt/RGB.dat", "/out/residuals/RGB.dat"}) {
        EXPECT_EQ(test::run(test::programPath("pyramid") + " check '" + dir.path() + f + "'").exitCode, 0) << f;
    }
    r = test::run(test::programPath("pyramid") + " verify --json '" + dir.file("out/RGB.dat") + "' --source '" +
                  dir.file("in.png") + "'");
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["levels"][2]["max_error"], 0);
    r = test::run(test::programPath("pyramid") + " verify '" + dir.file("out/residuals/RGB.dat") + "' --source '" +
                  dir.file("in.png") + "' --colour-residuals");
    EXPECT_EQ(r.exitCode, 0) << r.out;
    // A different source: the lossless file no longer matches.
    px[100] ^= 0x40;
    test::writeImage(dir.file("other.png"), 48, 40, 3, px, false);
    r = test::run(test::programPath("pyramid") + " verify '" + dir.file("out/RGB.dat") + "' --source '" +
                  dir.file("other.png") + "'");
    EXPECT_EQ(r.exitCode, 1) << r.out;
    // Bad input: one line, exit 1, no directory left behind.
    for (const std::string args :
         {" --border 3", " --compression zip", " --outputs tiff,png", " --tile-size 7", " --deflate-level 13",
          " --dxt-quality 4", " --residual-deflate-level 0"}) {
        r = test::run(test::programPath("preprocessOrtho") + " '" + dir.file("in.png") + "' -o '" + dir.file("bad") +
                      "'" + args);
        EXPECT_EQ(r.exitCode, 1) << args << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << r.err;
        EXPECT_FALSE(test::fileExists(dir.file("bad"))) << args;
    }
}

// --tile-size auto fits the tiles to the input: a 512 x 256 map is the upper half of a quad of
// 256-tiles pixel for pixel (192-tiles would resample it onto 768), a 300 x 150 one takes
// 152-tiles (a multiple of 4 for DXT); it is the default; given with --max-level or on cube
// faces it is refused.
TEST(PreprocessOrthoCli, TileSizeAutoFitsTheInputByDefault) {
    test::TempDir dir;
    for (const auto& [width, tileSize, maxLevel] : {std::tuple{512, 256, 1}, std::tuple{300, 152, 1}}) {
        const int height = width / 2;
        std::vector<uint16_t> px(static_cast<size_t>(width * height * 3));
        for (size_t k = 0; k < px.size(); ++k) {
            px[k] = static_cast<uint16_t>((k * 37) % 251);
        }
        const std::string in = dir.file("in" + std::to_string(width) + ".png");
        const std::string out = dir.file("auto" + std::to_string(width));
        test::writeImage(in, width, height, 3, px, false);
        auto r = test::run(test::programPath("preprocessOrtho") + " '" + in + "' -o '" + out +
                           "' --tile-size auto --quiet --report '" + out + ".json'");
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const auto report = nlohmann::json::parse(test::readFile(out + ".json"));
        EXPECT_EQ(report["tile_size"], tileSize) << width;
        EXPECT_EQ(report["max_level"], maxLevel) << width;
        const auto file = OrthoFileReader::open(out + "/dxt/RGB.dat");
        EXPECT_EQ(file->header().tileSize, tileSize);
        r = test::run(test::programPath("pyramid") + " verify --json '" + out + "/RGB.dat' --source '" + in + "'");
        ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
        if (width == 512) {
            EXPECT_EQ(nlohmann::json::parse(r.out)["levels"][maxLevel]["max_error"], 0); // the input's own pixels
        }
    }
    // auto is the default: the same files without --tile-size; --max-level alone keeps the
    // original tools' 192-tiles (a command naming its levels keeps its layout).
    const std::string in = dir.file("in512.png");
    auto r = test::run(test::programPath("preprocessOrtho") + " '" + in + "' -o '" + dir.file("default") + "' --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* file : {"/RGB.dat", "/dxt/RGB.dat", "/residuals/RGB.dat"}) {
        EXPECT_EQ(test::readFile(dir.file("default") + file), test::readFile(dir.file("auto512") + file)) << file;
    }
    r = test::run(test::programPath("preprocessOrtho") + " '" + in + "' -o '" + dir.file("levels") +
                  "' --max-level 2 --outputs tiff --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(OrthoFileReader::open(dir.file("levels") + "/RGB.dat")->header().tileSize, 192);
    EXPECT_EQ(OrthoFileReader::open(dir.file("levels") + "/RGB.dat")->header().maxLevel, 2);
    r = test::run(test::programPath("preprocessOrtho") + " '" + in + "' -o '" + dir.file("bad") +
                  "' --tile-size auto --max-level 2");
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(r.err, "preprocessOrtho: --max-level: is chosen by --tile-size auto: give one or the other\n");
    r = test::run(test::programPath("preprocessSphericalOrtho") + " '" + in + "' -o '" + dir.file("bad") +
                  "' --tile-size auto");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("--tile-size: 'auto' fits a planar input"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(test::fileExists(dir.file("bad")));
}

// --residual-deflate-level reaches the encoder: auto (the default) keeps level 2 for the root's
// colours and takes level 1 for these grainy residuals, tile for tile the blobs of those levels;
// 1, 2 and 12 each give their own file.
TEST(PreprocessOrthoCli, ResidualDeflateLevelReachesTheEncoder) {
    test::TempDir dir;
    std::vector<uint16_t> px(64 * 64 * 3);
    for (size_t k = 0; k < px.size(); ++k) {
        px[k] = static_cast<uint16_t>((k * 37) % 251);
    }
    test::writeImage(dir.file("in.png"), 64, 64, 3, px, false);
    for (const std::string level : {"", "auto", "1", "2", "12"}) {
        const auto r = test::run(test::programPath("preprocessOrtho") + " '" + dir.file("in.png") + "' -o '" +
                                 dir.file("l" + level) + "' --tile-size 16 --outputs residuals --quiet" +
                                 (level.empty() ? "" : " --residual-deflate-level " + level));
        ASSERT_EQ(r.exitCode, 0) << level << r.err;
    }
    const auto bytes = [&](const std::string& level) {
        return test::readFile(dir.file("l" + level + "/residuals/RGB.dat"));
    };
    EXPECT_EQ(bytes(""), bytes("auto"));
    EXPECT_NE(bytes("1"), bytes("2"));
    EXPECT_LT(bytes("12").size(), bytes("2").size());
    const auto chosen = OrthoFileReader::open(dir.file("lauto/residuals/RGB.dat"));
    const auto one = OrthoFileReader::open(dir.file("l1/residuals/RGB.dat"));
    const auto two = OrthoFileReader::open(dir.file("l2/residuals/RGB.dat"));
    EXPECT_EQ(chosen->readTileBytes(0, 0, 0), two->readTileBytes(0, 0, 0));
    int differing = 0;
    for (int l = 1; l <= chosen->header().maxLevel; ++l) {
        for (int ty = 0; ty < (1 << l); ++ty) {
            for (int tx = 0; tx < (1 << l); ++tx) {
                EXPECT_EQ(chosen->readTileBytes(l, tx, ty), one->readTileBytes(l, tx, ty))
                    << l << "," << tx << "," << ty;
                differing += one->readTileBytes(l, tx, ty) != two->readTileBytes(l, tx, ty);
            }
        }
    }
    EXPECT_GT(differing, 0);
}

// An input whose tiles a cache of --cache-mb cannot hold: the error names that flag and what
// the tiles need, in one line, and nothing is written; with the cache they need, the run works.
TEST(PreprocessOrthoCli, TilesBeyondTheCacheNameItsFlag) {
    test::TempDir dir;
    const std::string input = dir.file("big-tiles.tif");
    {
        // 64 x 48 RGB pixels in one tile of 1024 x 1024: 3 MB decoded.
        auto out = OIIO::ImageOutput::create(input);
        ASSERT_TRUE(out);
        OIIO::ImageSpec spec(64, 48, 3, OIIO::TypeDesc::UINT8);
        spec.tile_width = spec.tile_height = 1024;
        spec.attribute("compression", "zip");
        std::vector<uint8_t> pixels(64 * 48 * 3);
        for (size_t k = 0; k < pixels.size(); ++k) {
            pixels[k] = static_cast<uint8_t>(k % 251);
        }
        ASSERT_TRUE(out->open(input, spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && out->close())
            << out->geterror();
    }
    const std::string command = test::programPath("preprocessOrtho") + " " + shellQuoted(input) + " -o " +
                                shellQuoted(dir.file("out")) + " --tile-size 16 --quiet --cache-mb ";
    auto r = test::run(command + "4");
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(r.err, "preprocessOrtho: --cache-mb: " + input +
                         ": tiles of 1024 x 1024 samples (3 MB decoded) need a cache of at least 12 MB, not 4\n");
    EXPECT_FALSE(test::fileExists(dir.file("out")));
    r = test::run(command + "12");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(test::fileExists(dir.file("out/RGB.dat")));
}

// The report's JPEG error, when asked for, is what `pyramid verify` measures on the file, level
// by level; not asked for, it is null where a level holds JPEG tiles (never a 0 that would
// read as lossless), and 0 where it holds Deflate tiles only.
TEST(PreprocessOrthoCli, ReportsTheJpegErrorThatVerifyMeasures) {
    test::TempDir dir;
    std::vector<uint16_t> px(64 * 64 * 3);
    for (size_t k = 0; k < px.size(); ++k) {
        px[k] = static_cast<uint16_t>((k * 37 + (k / 192) * 11) % 251);
    }
    test::writeImage(dir.file("in.png"), 64, 64, 3, px, false);
    for (const bool measured : {true, false}) {
        SCOPED_TRACE(measured ? "--jpeg-error" : "without --jpeg-error");
        const std::string out = dir.file(measured ? "measured" : "plain");
        // original: levels 0 and 1 lie on the pyramid's edge (Deflate), level 2 has JPEG inside.
        auto r = test::run(test::programPath("preprocessOrtho") + " '" + dir.file("in.png") + "' -o '" + out +
                           "' --tile-size 16 --outputs tiff --compression original --quiet --report -" +
                           (measured ? " --jpeg-error" : ""));
        EXPECT_EQ(r.err, "");
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const auto report = nlohmann::json::parse(r.out);
        r = test::run(test::programPath("pyramid") + " verify --json '" + out + "/RGB.dat' --source '" +
                      dir.file("in.png") + "'");
        ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
        const auto verify = nlohmann::json::parse(r.out);
        ASSERT_EQ(report["levels"].size(), 3u);
        for (int l = 0; l < 3; ++l) {
            const auto& level = report["levels"][static_cast<size_t>(l)];
            EXPECT_EQ(level["jpeg_tiles"], l == 2 ? 4 : 0) << l;
            if (l < 2) {
                EXPECT_EQ(level["tiff_max_error"], 0) << l;
            } else if (measured) {
                EXPECT_GT(level["tiff_max_error"].get<int>(), 0);
                EXPECT_EQ(level["tiff_max_error"], verify["levels"][2]["max_error"]);
            } else {
                EXPECT_TRUE(level["tiff_max_error"].is_null()) << level;
            }
        }
    }
}

// YCbCr JPEG tiles: a one-line warning (the original runtime cannot read them), a file our
// readers check and verify as lossy, with the error the report measured.
TEST(PreprocessOrthoCli, YCbCrJpegTilesWarnAndVerify) {
    test::TempDir dir;
    std::vector<uint16_t> px(64 * 64 * 3);
    for (size_t k = 0; k < px.size(); ++k) {
        px[k] = static_cast<uint16_t>(100 + 60 * std::sin(static_cast<double>(k % 192) / 20.0 + static_cast<double>(k / 192) / 9.0));
    }
    test::writeImage(dir.file("in.png"), 64, 64, 3, px, false);
    auto r = test::run(test::programPath("preprocessOrtho") + " '" + dir.file("in.png") + "' -o '" + dir.file("out") +
                       "' --tile-size 16 --outputs tiff --compression jpeg-ycbcr --jpeg-error --report '" +
                       dir.file("r.json") + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.rfind("preprocessOrtho: warning: --compression jpeg-ycbcr: the original Proland runtime cannot read", 0), 0u)
        << r.err;
    const auto report = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_EQ(test::run(test::programPath("pyramid") + " check '" + dir.file("out/RGB.dat") + "'").exitCode, 0);
    const auto info = nlohmann::json::parse(
        test::run(test::programPath("pyramid") + " info --json '" + dir.file("out/RGB.dat") + "'").out);
    EXPECT_EQ(info["encodings"]["jpeg-ycbcr"], 21);
    r = test::run(test::programPath("pyramid") + " verify --json '" + dir.file("out/RGB.dat") + "' --source '" +
                  dir.file("in.png") + "'");
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    const auto verify = nlohmann::json::parse(r.out);
    for (size_t l = 0; l < 3; ++l) {
        EXPECT_EQ(verify["levels"][l]["lossy_tiles"], report["levels"][l]["jpeg_tiles"]) << l;
        EXPECT_EQ(verify["levels"][l]["max_error"], report["levels"][l]["tiff_max_error"]) << l;
        EXPECT_GT(report["levels"][l]["tiff_max_error"].get<int>(), 0) << l;
    }
}

} // namespace
} // namespace pyramid
