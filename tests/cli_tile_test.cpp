// `pyramid tile` as a user runs it: reconstructed and raw tiles of the original files, one-line
// errors with nothing written, and tiles as images (PNG, TIFF, EXR) holding the stored samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <tiffio.h>

#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using test::lines;
using test::programPath;
using test::run;
using test::shellQuoted;

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

} // namespace
} // namespace pyramid
