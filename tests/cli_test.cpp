// The programs as a user runs them: exit codes, one-line errors, JSON, no half-written output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>
#include <png.h>
#include <tiffio.h>
#include <zlib.h>

#include "formats/ortho_file.hpp"
#include "libpyramid/capi/pyramid.h"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::programPath;
using test::run;

std::string shellQuoted(const std::string& s) { return "'" + s + "'"; }

size_t lines(const std::string& s) { return static_cast<size_t>(std::count(s.begin(), s.end(), '\n')); }

TEST(PyramidInfo, DescribesTheOriginalFiles) {
    const auto r = run(programPath("pyramid") + " info --json " + shellQuoted(test::dataPath("proland/DEM.dat")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["kind"], "residual");
    EXPECT_EQ(j["header"]["min_level"], 3);
    EXPECT_EQ(j["header"]["tile_size"], 192);
    EXPECT_EQ(j["tiles"], 24);
    EXPECT_EQ(j["encodings"]["deflate-legacy"], 24);
    EXPECT_EQ(j["levels"][5]["tiles"], 16);
    EXPECT_EQ(j["levels"][0]["tile_side"], 29);
    const auto o = nlohmann::json::parse(run(programPath("pyramid") + " info --json " +
                                             shellQuoted(test::dataPath("proland/RGB.dat"))).out);
    EXPECT_EQ(o["kind"], "ortho");
    EXPECT_EQ(o["header"]["border"], 2);
    EXPECT_EQ(o["header"]["channels"], 4);
}

TEST(PyramidCheck, PassesGoodFilesAndFailsBrokenOnes) {
    for (const char* f : {"proland/DEM.dat", "proland/RGB.dat"}) {
        const auto r = run(programPath("pyramid") + " check --json " + shellQuoted(test::dataPath(f)));
        EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
        EXPECT_TRUE(nlohmann::json::parse(r.out)["ok"].get<bool>());
    }
    test::TempDir dir;
    std::string bytes = test::readFile(test::dataPath("proland/DEM.dat"));
    bytes[28 + 8 * 24 + 200] ^= 0x5a; // corrupt the root tile's compressed data
    {
        std::FILE* f = std::fopen(dir.file("bad.dat").c_str(), "wb");
        std::fwrite(bytes.data(), 1, bytes.size(), f);
        std::fclose(f);
    }
    const auto r = run(programPath("pyramid") + " check " + shellQuoted(dir.file("bad.dat")));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.out.find("tile (0,0,0)"), std::string::npos) << r.out;
    // The reason, on one line of stderr as for every failure: the program, the file, the tile.
    const std::string reason = "pyramid: " + dir.file("bad.dat") + ": ";
    EXPECT_EQ(r.err.rfind(reason, 0), 0u) << r.err;
    EXPECT_NE(r.err.find("tile (0,0,0)"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    // --json keeps the report on stdout, whole, and says the same on stderr.
    const auto j = run(programPath("pyramid") + " check --json " + shellQuoted(dir.file("bad.dat")));
    EXPECT_EQ(j.exitCode, 1);
    EXPECT_FALSE(nlohmann::json::parse(j.out)["ok"].get<bool>());
    EXPECT_EQ(j.err, r.err);
    // A file cut short fails to open: the reason names it, and nothing else is on stderr.
    {
        std::FILE* f = std::fopen(dir.file("short.dat").c_str(), "wb");
        std::fwrite(bytes.data(), 1, 40, f);
        std::fclose(f);
    }
    const auto s = run(programPath("pyramid") + " check " + shellQuoted(dir.file("short.dat")));
    EXPECT_EQ(s.exitCode, 1);
    EXPECT_EQ(s.err.rfind("pyramid: " + dir.file("short.dat") + ": ", 0), 0u) << s.err;
    EXPECT_EQ(s.err.find('\n'), s.err.size() - 1) << s.err;
    // A good file prints nothing on stderr.
    EXPECT_EQ(run(programPath("pyramid") + " check " + shellQuoted(test::dataPath("proland/DEM.dat"))).err, "");
}

TEST(PyramidTile, WritesReconstructedAndRawTiles) {
    test::TempDir dir;
    const std::string dem = shellQuoted(test::dataPath("proland/DEM.dat"));
    auto r = run(programPath("pyramid") + " tile " + dem + " 0 0 0 -o " + shellQuoted(dir.file("root.f32")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string f32 = test::readFile(dir.file("root.f32"));
    ASSERT_EQ(f32.size(), 29u * 29u * 4u);
    float first;
    std::memcpy(&first, f32.data(), 4);
    EXPECT_EQ(first, 1400.0f * 0.1f);
    r = run(programPath("pyramid") + " tile " + dem + " 5 3 3 --residual -o " + shellQuoted(dir.file("r.i16")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(test::readFile(dir.file("r.i16")).size(), 197u * 197u * 2u);
    r = run(programPath("pyramid") + " tile " + dem + " 5 3 3 -o " + shellQuoted(dir.file("z.tif")));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(test::fileExists(dir.file("z.tif")));
    r = run(programPath("pyramid") + " tile " + shellQuoted(test::dataPath("proland/RGB.dat")) + " 1 1 0 -o " +
            shellQuoted(dir.file("rgb.u8")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(test::readFile(dir.file("rgb.u8")).size(), 196u * 196u * 4u);
    // Mismatched output types and absent tiles: one line, exit 1, nothing written.
    r = run(programPath("pyramid") + " tile " + dem + " 0 0 0 -o " + shellQuoted(dir.file("z.i16")));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    r = run(programPath("pyramid") + " tile " + dem + " 2 1 0 -o " + shellQuoted(dir.file("none.f32")));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_FALSE(test::fileExists(dir.file("z.i16")));
    EXPECT_FALSE(test::fileExists(dir.file("none.f32")));
}

// Tiles as images hold the stored samples: the original RGBA tile (alpha 128 beside colours
// above it) keeps its colours in PNG and TIFF (unassociated alpha, never divided out or labelled
// premultiplied), and EXR holds int16 residuals and bytes as their values, not normalised.
TEST(PyramidTile, ImagesHoldTheStoredSamples) {
    test::TempDir dir;
    const std::string rgb = shellQuoted(test::dataPath("proland/RGB.dat"));
    const std::string dem = shellQuoted(test::dataPath("proland/DEM.dat"));
    for (const char* out : {"t.u8", "t.png", "t.tif", "t.exr"}) {
        const auto r = run(programPath("pyramid") + " tile " + rgb + " 1 0 1 -o " + shellQuoted(dir.file(out)));
        ASSERT_EQ(r.exitCode, 0) << out << ": " << r.err;
    }
    for (const char* out : {"r.i16", "r.tif", "r.exr"}) {
        const auto r = run(programPath("pyramid") + " tile " + dem + " 0 0 0 --residual -o " + shellQuoted(dir.file(out)));
        ASSERT_EQ(r.exitCode, 0) << out << ": " << r.err;
    }
    // Image files are north up: row j of the image is row side - 1 - j of the raw samples.
    auto readImage = [](const std::string& path, OIIO::TypeDesc type, int& side, int& channels) {
        OIIO::ImageSpec config; // the samples as stored, alpha not multiplied in
        config.attribute("oiio:UnassociatedAlpha", 1);
        auto in = OIIO::ImageInput::open(path, &config);
        EXPECT_TRUE(in) << path;
        std::vector<float> values;
        if (!in) {
            return values;
        }
        const OIIO::ImageSpec spec = in->spec();
        side = spec.width;
        channels = spec.nchannels;
        std::vector<uint8_t> bytes(spec.image_pixels() * static_cast<size_t>(channels) * type.size());
        EXPECT_TRUE(in->read_image(0, 0, 0, -1, type, bytes.data())) << path;
        values.resize(bytes.size() / type.size());
        for (size_t i = 0; i < values.size(); ++i) {
            if (type == OIIO::TypeDesc::UINT8) {
                values[i] = bytes[i];
            } else if (type == OIIO::TypeDesc::INT16) {
                int16_t v;
                std::memcpy(&v, &bytes[2 * i], 2);
                values[i] = v;
            } else {
                std::memcpy(&values[i], &bytes[4 * i], 4);
            }
        }
        return values;
    };
    auto rawRowsNorthUp = [](const std::string& raw, size_t sampleBytes, int side, int channels) {
        std::vector<float> values(raw.size() / sampleBytes);
        const size_t row = static_cast<size_t>(side) * static_cast<size_t>(channels);
        for (size_t i = 0; i < values.size(); ++i) {
            const size_t j = static_cast<size_t>(side) - 1 - i / row, at = j * row + i % row;
            if (sampleBytes == 1) {
                values[i] = static_cast<uint8_t>(raw[at]);
            } else {
                int16_t v;
                std::memcpy(&v, &raw[2 * at], 2);
                values[i] = v;
            }
        }
        return values;
    };
    const std::vector<float> colours = rawRowsNorthUp(test::readFile(dir.file("t.u8")), 1, 196, 4);
    ASSERT_EQ(colours.size(), 196u * 196u * 4u);
    bool alphaBelowColours = false; // the case a premultiplied reading changes
    for (size_t i = 0; i + 3 < colours.size() && !alphaBelowColours; i += 4) {
        alphaBelowColours = colours[i + 3] < 255 && colours[i] > colours[i + 3];
    }
    EXPECT_TRUE(alphaBelowColours);
    for (const auto& [name, type] : {std::pair{"t.png", OIIO::TypeDesc::UINT8}, std::pair{"t.tif", OIIO::TypeDesc::UINT8},
                                     std::pair{"t.exr", OIIO::TypeDesc::FLOAT}}) {
        int side = 0, channels = 0;
        EXPECT_EQ(readImage(dir.file(name), type, side, channels), colours) << name;
        EXPECT_EQ(side, 196) << name;
        EXPECT_EQ(channels, 4) << name;
    }
    TIFF* tif = TIFFOpen(dir.file("t.tif").c_str(), "r");
    ASSERT_NE(tif, nullptr);
    uint16_t extras = 0;
    uint16_t* kinds = nullptr;
    ASSERT_EQ(TIFFGetField(tif, TIFFTAG_EXTRASAMPLES, &extras, &kinds), 1);
    ASSERT_EQ(extras, 1);
    EXPECT_EQ(kinds[0], EXTRASAMPLE_UNASSALPHA);
    TIFFClose(tif);
    const std::vector<float> residuals = rawRowsNorthUp(test::readFile(dir.file("r.i16")), 2, 29, 1);
    ASSERT_EQ(residuals.size(), 29u * 29u); // the root tile: 24 intervals, 2-sample borders
    EXPECT_GT(*std::max_element(residuals.begin(), residuals.end()), 255.0f); // beyond what normalising keeps
    for (const auto& [name, type] : {std::pair{"r.tif", OIIO::TypeDesc::INT16}, std::pair{"r.exr", OIIO::TypeDesc::FLOAT}}) {
        int side = 0, channels = 0;
        EXPECT_EQ(readImage(dir.file(name), type, side, channels), residuals) << name;
        EXPECT_EQ(channels, 1) << name;
    }
}

// TIFF and PNG inputs are read without OpenImageIO: with its module unavailable they still
// work, and only a format that needs it (EXR) fails, naming the file and the module.
TEST(ImageIoModule, TiffAndPngNeedNoOpenImageIO) {
    test::TempDir dir;
    const std::string without = "PYRAMID_OIIO_MODULE=" + shellQuoted(dir.file("missing.so")) + " ";
    auto r = run(without + programPath("preprocessDem") + " --quiet " + shellQuoted(test::samplePath("dem.tif")) +
                 " -o " + shellQuoted(dir.file("DEM.dat")));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    r = run(without + programPath("preprocessOrtho") + " --quiet --outputs tiff " +
            shellQuoted(test::samplePath("bluemarble.png")) + " -o " + shellQuoted(dir.file("ortho")));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    std::vector<uint16_t> grey(33 * 33);
    for (size_t k = 0; k < grey.size(); ++k) {
        grey[k] = static_cast<uint16_t>(k % 256);
    }
    test::writeImage(dir.file("grey.exr"), 33, 33, 1, grey, false);
    r = run(without + programPath("preprocessDem") + " --quiet " + shellQuoted(dir.file("grey.exr")) + " -o " +
            shellQuoted(dir.file("EXR.dat")));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(dir.file("grey.exr") + ": needs OpenImageIO, but the image I/O module cannot be loaded"),
              std::string::npos) << r.err;
    EXPECT_FALSE(test::fileExists(dir.file("EXR.dat")));
    // With the module (the build's own), the same EXR is read.
    r = run(programPath("preprocessDem") + " --quiet " + shellQuoted(dir.file("grey.exr")) + " -o " +
            shellQuoted(dir.file("EXR.dat")));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    // Image output goes through the module too.
    r = run(without + programPath("pyramid") + " tile " + shellQuoted(dir.file("EXR.dat")) + " 0 0 0 -o " +
            shellQuoted(dir.file("root.tif")));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("image I/O module"), std::string::npos) << r.err;
    EXPECT_FALSE(test::fileExists(dir.file("root.tif")));
}

// --version names the program and libpyramid's version, then each library the way the library
// names itself when asked at run time; a module that cannot be loaded is said so, not fatal.
TEST(Version, EveryProgramNamesItsLibraries) {
    const std::string tiff = TIFFGetVersion();
    const size_t at = tiff.find("Version ") + 8;
    const std::string tiffVersion = tiff.substr(at, tiff.find_first_of(" \n", at) - at);
    const auto png = static_cast<int>(png_access_version_number());
    const std::string pngVersion =
        std::to_string(png / 10000) + "." + std::to_string(png / 100 % 100) + "." + std::to_string(png % 100);
    const int oiio = OIIO::openimageio_version();
    const std::string oiioVersion =
        std::to_string(oiio / 10000) + "." + std::to_string(oiio / 100 % 100) + "." + std::to_string(oiio % 100);
    for (const std::string program :
         {"pyramid", "preprocessDem", "preprocessOrtho", "preprocessSphericalDem", "preprocessSphericalOrtho",
          "preprocessAperture", "preprocessSphericalAperture"}) {
        const auto r = run(programPath(program) + " --version");
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_EQ(r.out.substr(0, r.out.find('\n')),
                  program + " " + pyramid_version_string() + " (libpyramid)");
        for (const std::string& line : {"  libtiff " + tiffVersion, "  zlib " + std::string(zlibVersion()),
                                       "  libpng " + pngVersion,
                                       "  OpenImageIO " + oiioVersion}) {
            EXPECT_NE(r.out.find(line + "\n"), std::string::npos) << program << ": no '" << line << "' in\n" << r.out;
        }
        for (const std::string name : {"libdeflate ", "GeographicLib ", "libgeotiff ", "OpenMP ", "build: "}) {
            EXPECT_NE(r.out.find("\n  " + name), std::string::npos) << program << ": no " << name << "in\n" << r.out;
        }
    }
    test::TempDir dir;
    const auto r = run("PYRAMID_OIIO_MODULE=" + shellQuoted(dir.file("missing.so")) + " " + programPath("pyramid") +
                       " --version");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("  OpenImageIO not loaded: "), std::string::npos) << r.out;
}

// JSON output has one spelling, --report FILE|-, in every command; --json is --report -.
// The inspection commands print their text on stdout unless the JSON goes there; the two
// spellings give the same JSON, and naming both is a usage error.
TEST(Report, OneSpellingForEveryCommand) {
    test::TempDir dir;
    const std::string dem = shellQuoted(test::dataPath("proland/DEM.dat"));
    for (const std::string command : {"info", "check"}) {
        const std::string base = programPath("pyramid") + " " + command + " " + dem;
        const auto alias = run(base + " --json");
        ASSERT_EQ(alias.exitCode, 0) << alias.err;
        const auto dash = run(base + " --report -");
        ASSERT_EQ(dash.exitCode, 0) << dash.err;
        EXPECT_EQ(nlohmann::json::parse(dash.out), nlohmann::json::parse(alias.out)) << command;
        const std::string file = dir.file(command + ".json");
        const auto toFile = run(base + " --report " + shellQuoted(file));
        ASSERT_EQ(toFile.exitCode, 0) << toFile.err;
        EXPECT_EQ(nlohmann::json::parse(test::readFile(file)), nlohmann::json::parse(alias.out)) << command;
        EXPECT_FALSE(nlohmann::json::accept(toFile.out)) << "the text stays on stdout";
        EXPECT_FALSE(toFile.out.empty());
        EXPECT_EQ(run(base + " --json --report " + shellQuoted(dir.file("both.json"))).exitCode, 2) << command;
        EXPECT_FALSE(test::fileExists(dir.file("both.json")));
    }
    // A builder: --json prints the report that --report FILE writes.
    test::writeFloatRaster(dir.file("in.tif"), 65, 65, test::syntheticHeights(65, 65));
    const std::string build = programPath("preprocessDem") + " -q " + shellQuoted(dir.file("in.tif")) + " -o ";
    const auto alias = run(build + shellQuoted(dir.file("a/DEM.dat")) + " --json");
    ASSERT_EQ(alias.exitCode, 0) << alias.err;
    ASSERT_EQ(run(build + shellQuoted(dir.file("b/DEM.dat")) + " --report " + shellQuoted(dir.file("b.json"))).exitCode, 0);
    auto printed = nlohmann::json::parse(alias.out), written = nlohmann::json::parse(test::readFile(dir.file("b.json")));
    EXPECT_EQ(printed["levels"], written["levels"]);
    EXPECT_EQ(printed["bytes"], written["bytes"]);
}

class PreprocessDemCli : public ::testing::Test {
protected:
    test::TempDir dir;
    std::string input = dir.file("dem.tif");
    void SetUp() override { test::writeFloatRaster(input, 65, 65, test::syntheticHeights(65, 65)); }

    // Runs preprocessDem expecting failure: exit code `code`, one line on stderr mentioning
    // `mention`, and no file left in the output directory.
    void expectFailure(const std::string& args, int code, const std::string& mention) {
        const std::string outDir = dir.file("out");
        std::filesystem::create_directories(outDir);
        const auto r = run(programPath("preprocessDem") + " " + args + " -o " + shellQuoted(outDir + "/DEM.dat"));
        EXPECT_EQ(r.exitCode, code) << args << "\n" << r.err;
        EXPECT_EQ(lines(r.err), 1u) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(mention), std::string::npos) << args << "\n" << r.err;
        EXPECT_TRUE(std::filesystem::is_empty(outDir)) << args;
    }
};

TEST_F(PreprocessDemCli, BuildsVerifiesAndReports) {
    const std::string out = dir.file("DEM.dat");
    auto r = run(programPath("preprocessDem") + " " + shellQuoted(input) + " -o " + shellQuoted(out) +
                 " --tile-size 16 --root-tile-size 4 --scale 0.5 --quiet --report " + shellQuoted(dir.file("r.json")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, ""); // --quiet
    const auto report = nlohmann::json::parse(test::readFile(dir.file("r.json")));
    EXPECT_EQ(report["header"]["max_level"], 4);
    EXPECT_EQ(report["header"]["scale"], 0.5);
    for (const auto& l : report["levels"]) {
        EXPECT_LE(l["max_error"].get<double>(), 0.25 + 1e-3);
    }
    r = run(programPath("pyramid") + " verify --json " + shellQuoted(out) + " --source " + shellQuoted(input));
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_TRUE(nlohmann::json::parse(r.out)["ok"].get<bool>());
    r = run(programPath("pyramid") + " check " + shellQuoted(out));
    EXPECT_EQ(r.exitCode, 0) << r.out;
    // Progress and a summary on stderr without --quiet; the same bytes again.
    r = run(programPath("pyramid") + " dem " + shellQuoted(input) + " -o " + shellQuoted(dir.file("again.dat")) +
            " --tile-size 16 --root-tile-size 4 --scale 0.5 --threads 1");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("100%"), std::string::npos) << r.err;
    EXPECT_EQ(test::readFile(out), test::readFile(dir.file("again.dat")));
}

TEST_F(PreprocessDemCli, VerifyFailsAgainstTheWrongSource) {
    const std::string out = dir.file("DEM.dat");
    ASSERT_EQ(run(programPath("preprocessDem") + " -q " + shellQuoted(input) + " -o " + shellQuoted(out)).exitCode, 0);
    std::vector<float> other = test::syntheticHeights(65, 65);
    other[65 * 30 + 30] += 10.0f;
    test::writeFloatRaster(dir.file("other.tif"), 65, 65, other);
    const auto r = run(programPath("pyramid") + " verify " + shellQuoted(out) + " --source " + shellQuoted(dir.file("other.tif")));
    EXPECT_EQ(r.exitCode, 1) << r.out;
    EXPECT_NE(r.out.find("BEYOND BOUND"), std::string::npos) << r.out;
}

TEST_F(PreprocessDemCli, BadInputFailsCleanly) {
    expectFailure(shellQuoted(dir.file("missing.tif")), 1, "missing.tif: no such file");
    {
        std::FILE* f = std::fopen(dir.file("junk.tif").c_str(), "wb");
        std::fputs("this is not an image", f);
        std::fclose(f);
    }
    expectFailure(shellQuoted(dir.file("junk.tif")), 1, "junk.tif");
    std::vector<float> withNan = test::syntheticHeights(65, 65);
    withNan[65 * 10 + 20] = std::nanf("");
    test::writeFloatRaster(dir.file("nan.tif"), 65, 65, withNan);
    expectFailure(shellQuoted(dir.file("nan.tif")), 1, "NaN height at column 20, row 10");
    expectFailure(shellQuoted(input) + " --tile-size 100 --root-tile-size 24", 1, "--root-tile-size");
    expectFailure(shellQuoted(input) + " --scale 0", 1, "--scale");
    expectFailure(shellQuoted(input) + " --band 2", 1, "--band");
    expectFailure(shellQuoted(input) + " --no-such-option", 2, "no-such-option");
    // A 16-bit PNG cut short: its header reads, its pixels fail once encoding has started.
    std::vector<uint16_t> heights(257 * 257);
    for (size_t k = 0; k < heights.size(); ++k) {
        heights[k] = static_cast<uint16_t>((k * 2654435761u) >> 16);
    }
    test::writeImage(dir.file("whole.png"), 257, 257, 1, heights, true);
    const std::string whole = test::readFile(dir.file("whole.png"));
    {
        std::FILE* f = std::fopen(dir.file("cut.png").c_str(), "wb");
        std::fwrite(whole.data(), 1, whole.size() / 2, f);
        std::fclose(f);
    }
    const std::string outDir = dir.file("out");
    const auto r = run(programPath("preprocessDem") + " " + shellQuoted(dir.file("cut.png")) + " -o " +
                       shellQuoted(outDir + "/DEM.dat"));
    EXPECT_EQ(r.exitCode, 1) << r.err;
    // One line, ours, naming the file and the problem.
    EXPECT_EQ(r.err, "preprocessDem: " + dir.file("cut.png") + ": cannot read: damaged or truncated PNG (Read Error)\n");
    EXPECT_TRUE(std::filesystem::is_empty(outDir));
}

} // namespace
} // namespace pyramid

namespace pyramid {
namespace {

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
