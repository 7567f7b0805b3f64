// Heights are finite numbers: a float DEM's +Inf and -Inf samples are an error naming the file,
// column and row, unless declared nodata (--nodata inf / -inf / +inf), in preprocessDem,
// preprocessSphericalDem and mosaics of both; `pyramid verify` fails on any non-finite value and
// its reports never print one. Numbers given as text are read whole, whatever the locale.
#include <cctype>
#include <clocale>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tiffio.h>

#include "formats/error.hpp"
#include "formats/residual_file.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/dem/dem_sampling.hpp"
#include "libpyramid/input/nodata_text.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/verify/dem_verify.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::programPath;
using test::run;

constexpr int kSide = 385; // 384 intervals: preprocessDem's default pyramid holds it exactly
constexpr float kInf = std::numeric_limits<float>::infinity();
// Where the two infinite samples lie (column, row; row 0 = north).
constexpr int kPlusColumn = 200, kPlusRow = 120;
constexpr int kMinusColumn = 300, kMinusRow = 50;

std::string quoted(const std::string& s) { return "'" + s + "'"; }

size_t at(int column, int row) { return static_cast<size_t>(column) + static_cast<size_t>(row) * kSide; }

// The 385^2 heights with +Inf at (kPlusColumn, kPlusRow) and -Inf at (kMinusColumn, kMinusRow)
// when asked for.
std::vector<float> heights(bool plus, bool minus) {
    std::vector<float> h = test::syntheticHeights(kSide, kSide);
    if (plus) {
        h[at(kPlusColumn, kPlusRow)] = kInf;
    }
    if (minus) {
        h[at(kMinusColumn, kMinusRow)] = -kInf;
    }
    return h;
}

std::string placeText(const char* sign, int column, int row) {
    return std::string(sign) + "Inf height at column " + std::to_string(column) + ", row " + std::to_string(row);
}

// Whether a report's text, with the test directory's name taken out (its random letters could
// spell anything), mentions NaN or an infinity.
bool mentionsNonFinite(std::string text, const test::TempDir& dir) {
    for (size_t k = text.find(dir.path()); k != std::string::npos; k = text.find(dir.path())) {
        text.erase(k, dir.path().size());
    }
    for (char& c : text) {
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return text.find("nan") != std::string::npos || text.find("inf") != std::string::npos;
}

// One line on stderr naming `file` and one of `places`, exit 1, nothing at `output`.
void expectRefused(const test::RunResult& r, const std::string& file, const std::vector<std::string>& places,
                   const std::string& output) {
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.err.find(file + ": "), std::string::npos) << r.err;
    bool named = false;
    for (const std::string& p : places) {
        named = named || r.err.find(p) != std::string::npos;
    }
    EXPECT_TRUE(named) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(output)) << output;
}

// A 64-bit DEM whose finite value lies past float32's range reads as an infinity: the error says
// so, rather than advising a nodata value that would drop it.
TEST(NonFiniteHeights, A64BitHeightPastFloat32sRangeIsNamedSo) {
    test::TempDir dir;
    const std::string file = dir.file("wide.tif"), out = dir.file("DEM.dat");
    const std::vector<float> h = heights(false, false);
    {
        TIFF* t = TIFFOpen(file.c_str(), "w");
        ASSERT_NE(t, nullptr);
        TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(kSide));
        TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(kSide));
        TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, uint16_t{64});
        TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, uint16_t{SAMPLEFORMAT_IEEEFP});
        TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, uint16_t{1});
        TIFFSetField(t, TIFFTAG_PHOTOMETRIC, uint16_t{PHOTOMETRIC_MINISBLACK});
        TIFFSetField(t, TIFFTAG_PLANARCONFIG, uint16_t{PLANARCONFIG_CONTIG});
        TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, static_cast<uint32_t>(kSide));
        std::vector<double> row(kSide);
        for (int y = 0; y < kSide; ++y) {
            for (int x = 0; x < kSide; ++x) {
                row[static_cast<size_t>(x)] = h[at(x, y)];
            }
            if (y == kPlusRow) {
                row[kPlusColumn] = 4e303;
            }
            ASSERT_EQ(TIFFWriteScanline(t, row.data(), static_cast<uint32_t>(y), 0), 1);
        }
        TIFFClose(t);
    }
    const test::RunResult r = run(programPath("preprocessDem") + " -q " + quoted(file) + " -o " + quoted(out));
    expectRefused(r, file,
                  {"+Inf, or a height above 3.4e38, at column " + std::to_string(kPlusColumn) + ", row " +
                   std::to_string(kPlusRow) + ": heights are read as float32"},
                  out);
}

TEST(NonFiniteHeights, PlanarInfinitiesAreErrorsUnlessDeclaredNodata) {
    test::TempDir dir;
    const std::string both = dir.file("both.tif"), plus = dir.file("plus.tif"), out = dir.file("DEM.dat");
    test::writeFloatRaster(both, kSide, kSide, heights(true, true));
    test::writeFloatRaster(plus, kSide, kSide, heights(true, false));
    const std::string dem = programPath("preprocessDem") + " -q ";
    expectRefused(run(dem + quoted(both) + " -o " + quoted(out)), both,
                  {placeText("+", kPlusColumn, kPlusRow), placeText("-", kMinusColumn, kMinusRow)}, out);
    // Declaring one infinity leaves the other an error.
    expectRefused(run(dem + quoted(both) + " --nodata inf -o " + quoted(out)), both,
                  {placeText("-", kMinusColumn, kMinusRow)}, out);
    expectRefused(run(dem + quoted(both) + " --nodata -inf -o " + quoted(out)), both,
                  {placeText("+", kPlusColumn, kPlusRow)}, out);
    expectRefused(run(dem + quoted(plus) + " -o " + quoted(out)), plus, {placeText("+", kPlusColumn, kPlusRow)}, out);
    // Declared, the infinity is a hole: filled, counted, and named as text in the report.
    for (const char* spelling : {"inf", "+inf", "Infinity"}) {
        const auto r = run(dem + quoted(plus) + " --nodata " + spelling + " -o " + quoted(out) + " --report " +
                           quoted(dir.file("r.json")));
        ASSERT_EQ(r.exitCode, 0) << spelling << ": " << r.err;
        const nlohmann::json j = nlohmann::json::parse(test::readFile(dir.file("r.json")));
        EXPECT_EQ(j["input"]["nodata"], "inf") << spelling;
        EXPECT_EQ(j["nodata_filled"], 1) << spelling;
    }
    // The pyramid is within its bound of every other sample; verify reads the source by the
    // same rule, so without the declaration the infinity is the same error.
    const auto verified = run(programPath("pyramid") + " verify " + quoted(out) + " --source " + quoted(plus) +
                              " --nodata inf");
    EXPECT_EQ(verified.exitCode, 0) << verified.out << verified.err;
    EXPECT_FALSE(mentionsNonFinite(verified.out, dir)) << verified.out;
    const auto json = run(programPath("pyramid") + " verify --json " + quoted(out) + " --source " + quoted(plus) +
                          " --nodata +inf");
    EXPECT_EQ(json.exitCode, 0) << json.err;
    EXPECT_EQ(nlohmann::json::parse(json.out)["ok"], true);
    const auto unknown = run(programPath("pyramid") + " verify " + quoted(out) + " --source " + quoted(plus));
    EXPECT_EQ(unknown.exitCode, 1);
    EXPECT_NE(unknown.err.find(placeText("+", kPlusColumn, kPlusRow)), std::string::npos) << unknown.err;
    EXPECT_EQ(unknown.out, "");
}

TEST(NonFiniteHeights, NegativeInfinityAsNodata) {
    test::TempDir dir;
    std::vector<float> h = heights(false, true);
    h[at(10, 11)] = -kInf;
    const std::string minus = dir.file("minus.tif");
    test::writeFloatRaster(minus, kSide, kSide, h);
    DemEncodeOptions o;
    o.nodata = -std::numeric_limits<double>::infinity();
    const DemReport report = encodeDem(minus, dir.file("DEM.dat"), o);
    EXPECT_EQ(report.nodataFilled, 2);
    EXPECT_EQ(toJson(report)["input"]["nodata"], "-inf");
    o.nodata = std::numeric_limits<double>::infinity();
    try {
        encodeDem(minus, dir.file("DEM2.dat"), o);
        FAIL() << "-Inf accepted with +Inf as the nodata value";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_TRUE(what.find(placeText("-", 10, 11)) != std::string::npos ||
                    what.find(placeText("-", kMinusColumn, kMinusRow)) != std::string::npos)
            << what;
        EXPECT_NE(what.find("(declare -inf the nodata value"), std::string::npos) << what;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("DEM2.dat")));
}

TEST(NonFiniteHeights, AFileDeclaringInfinityAsNodata) {
    test::TempDir dir;
    test::GeoTiffTags tags;
    tags.gdalNodata = "inf";
    test::writeGeoTiff(dir.file("declared.tif"), kSide, kSide, heights(true, false), tags);
    const auto source = RasterSource::open(dir.file("declared.tif"));
    ASSERT_TRUE(source->info().nodata.has_value());
    EXPECT_EQ(*source->info().nodata, std::numeric_limits<double>::infinity());
    const DemReport report = encodeDem(dir.file("declared.tif"), dir.file("DEM.dat"), {});
    EXPECT_EQ(report.nodataFilled, 1);
}

// The mosaic's west file holds columns 0..192, the east one 193..384 (one grid, 1/384 degree
// pixels): an infinity is named in the file that holds it, at its own column and row.
void writeMosaic(const test::TempDir& dir, const std::vector<float>& h, bool geographicGlobe) {
    const int split = 193;
    const double step = geographicGlobe ? 360.0 / kSide : 1.0 / 384.0;
    const double west = geographicGlobe ? -180.0 : 10.0, north = geographicGlobe ? 90.0 : 46.0;
    const double stepY = geographicGlobe ? 180.0 / kSide : step;
    for (int part = 0; part < 2; ++part) {
        const int c0 = part == 0 ? 0 : split, width = part == 0 ? split : kSide - split;
        std::vector<float> values(static_cast<size_t>(width) * kSide);
        for (int row = 0; row < kSide; ++row) {
            for (int c = 0; c < width; ++c) {
                values[static_cast<size_t>(c + row * width)] = h[at(c0 + c, row)];
            }
        }
        test::GeoTiffTags tags = test::geographicTags(4326, west + c0 * step, north, step);
        tags.pixelScale = {step, stepY, 0.0};
        test::writeGeoTiff(dir.file(part == 0 ? "west.tif" : "east.tif"), width, kSide, values, tags);
    }
}

TEST(NonFiniteHeights, MosaicsNameTheFileThatHoldsTheInfinity) {
    test::TempDir dir;
    writeMosaic(dir, heights(false, true), false);
    const std::string out = dir.file("DEM.dat");
    expectRefused(run(programPath("preprocessDem") + " -q " + quoted(dir.file("west.tif")) + " " +
                      quoted(dir.file("east.tif")) + " -o " + quoted(out)),
                  dir.file("east.tif"), {placeText("-", kMinusColumn - 193, kMinusRow)}, out);
    const auto r = run(programPath("preprocessDem") + " -q " + quoted(dir.file("west.tif")) + " " +
                       quoted(dir.file("east.tif")) + " --nodata -inf -o " + quoted(out));
    EXPECT_EQ(r.exitCode, 0) << r.err;
}

TEST(NonFiniteHeights, SphericalInfinitiesAreErrorsUnlessDeclaredNodata) {
    test::TempDir dir;
    // A global plate carree: +Inf at 7.5 E, 33.7 N (face 3), -Inf at 101.0 E, 66.4 N (face 1).
    const std::string both = dir.file("both.tif"), out = dir.file("planet");
    test::writeFloatRaster(both, kSide, kSide, heights(true, true));
    const std::string sphere = programPath("preprocessSphericalDem") +
                               " -q --tile-size 32 --root-tile-size 8 --max-level 6 " + quoted(both) + " -o " +
                               quoted(out);
    expectRefused(run(sphere + " --faces 3"), both, {placeText("+", kPlusColumn, kPlusRow)}, out);
    const auto ok = run(sphere + " --faces 3 --nodata inf");
    EXPECT_EQ(ok.exitCode, 0) << ok.err;
    EXPECT_TRUE(std::filesystem::exists(out + "/DEM3.dat"));
    std::filesystem::remove_all(out);
    // Face 1 (and the borders its neighbours read from it) holds the -Inf.
    expectRefused(run(sphere + " --nodata inf"), both, {placeText("-", kMinusColumn, kMinusRow)}, out);
    expectRefused(run(sphere + " --nodata -inf"), both, {placeText("+", kPlusColumn, kPlusRow)}, out);
}

TEST(NonFiniteHeights, SphericalMosaicsNameTheFile) {
    test::TempDir dir;
    writeMosaic(dir, heights(false, true), true);
    const std::string out = dir.file("planet");
    expectRefused(run(programPath("preprocessSphericalDem") + " -q --tile-size 32 --root-tile-size 8 --max-level 6 " +
                      "--faces 1 " + quoted(dir.file("west.tif")) + " " + quoted(dir.file("east.tif")) + " -o " +
                      quoted(out)),
                  dir.file("east.tif"), {placeText("-", kMinusColumn - 193, kMinusRow)}, out);
}

// A residual file whose rebuilt heights overflow float32: scale 3e38, a residual of 2.
void writeOverflowingPyramid(const std::string& path) {
    ResidualHeader h;
    h.tileSize = 4;
    h.scale = 3e38f;
    ResidualFileWriter writer(path, h);
    std::vector<int16_t> residuals(static_cast<size_t>(h.tileSamples(0) * h.tileSamples(0)), 0);
    residuals[static_cast<size_t>(3 + 3 * h.tileSamples(0))] = 2;
    writer.writeTile(0, 0, 0, residuals);
    writer.commit();
}

TEST(NonFiniteHeights, VerifyFailsOnNonFiniteReconstructionsAndNeverPrintsThem) {
    test::TempDir dir;
    writeOverflowingPyramid(dir.file("DEM.dat"));
    test::writeFloatRaster(dir.file("flat.tif"), 5, 5, std::vector<float>(25, 0.0f));
    const DemVerifyReport report = verifyDem(dir.file("DEM.dat"), dir.file("flat.tif"), {});
    ASSERT_EQ(report.levels.size(), 1u);
    EXPECT_EQ(report.levels[0].samples, 25);
    EXPECT_GE(report.levels[0].nonFinite, 1);
    EXPECT_TRUE(std::isfinite(report.levels[0].maxError));
    EXPECT_TRUE(std::isfinite(report.levels[0].rmsError));
    EXPECT_FALSE(report.ok());

    const auto text = run(programPath("pyramid") + " verify " + quoted(dir.file("DEM.dat")) + " --source " +
                          quoted(dir.file("flat.tif")));
    EXPECT_EQ(text.exitCode, 1) << text.out << text.err;
    EXPECT_NE(text.out.find("NON-FINITE"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("FAILED"), std::string::npos) << text.out;
    EXPECT_FALSE(mentionsNonFinite(text.out, dir)) << text.out;
    const auto json = run(programPath("pyramid") + " verify --json " + quoted(dir.file("DEM.dat")) + " --source " +
                          quoted(dir.file("flat.tif")));
    EXPECT_EQ(json.exitCode, 1);
    const nlohmann::json j = nlohmann::json::parse(json.out);
    EXPECT_EQ(j["ok"], false);
    EXPECT_GE(j["levels"][0]["non_finite"].get<int64_t>(), 1);
    EXPECT_TRUE(j["levels"][0]["max_error"].is_number());
    EXPECT_TRUE(j["levels"][0]["rms_error"].is_number());
    EXPECT_FALSE(mentionsNonFinite(json.out, dir)) << json.out;
    EXPECT_EQ(json.out.find("null"), std::string::npos) << json.out;
}

TEST(NumberText, WholeTextOnly) {
    EXPECT_EQ(tryParseNumber("-9999"), -9999.0);
    EXPECT_EQ(tryParseNumber("+2.5e3"), 2500.0);
    EXPECT_EQ(tryParseNumber(".5"), 0.5);
    for (const char* bad : {"-9999abc", "", " 1", "1 ", "1,5", "0x10", "+", "+-1", "++1", "inf", "nan", "1e999", "-"}) {
        EXPECT_FALSE(tryParseNumber(bad).has_value()) << "'" << bad << "'";
    }
    EXPECT_THROW(parseNumber("12abc", "--scale"), Error);
}

TEST(NumberText, WholeNumbersAreTheWholeText) {
    EXPECT_EQ(readWholeNumber<int>("4326"), 4326);
    EXPECT_EQ(readWholeNumber<int>("-7"), -7);
    EXPECT_EQ(readWholeNumber<int64_t>("9000000000"), int64_t{9000000000});
    for (const char* bad : {"", " 1", "1 ", "+1", "1.0", "1e3", "12abc", "0x10", "-", "3,", "2147483648"}) {
        EXPECT_FALSE(readWholeNumber<int>(bad).has_value()) << "'" << bad << "'";
    }
}

TEST(NumberText, NodataValues) {
    EXPECT_TRUE(std::isnan(*tryParseNodataText("nan")));
    EXPECT_TRUE(std::isnan(*tryParseNodataText("NaN")));
    EXPECT_TRUE(std::isnan(*tryParseNodataText("-nan")));
    EXPECT_EQ(*tryParseNodataText("inf"), std::numeric_limits<double>::infinity());
    EXPECT_EQ(*tryParseNodataText("+inf"), std::numeric_limits<double>::infinity());
    EXPECT_EQ(*tryParseNodataText("-inf"), -std::numeric_limits<double>::infinity());
    EXPECT_EQ(*tryParseNodataText("-3.4028234663852886e+38"), -3.4028234663852886e+38);
    EXPECT_FALSE(tryParseNodataText("-9999abc").has_value());
    EXPECT_FALSE(tryParseNodataText("infinite").has_value());
    try {
        parseNodataChoice("-9999abc", "--nodata");
        FAIL() << "-9999abc accepted";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "--nodata: '-9999abc' is not a number, nan, inf, -inf or none");
    }
    EXPECT_TRUE(parseNodataChoice("none", "--nodata").ignoreDeclared);
    EXPECT_EQ(*parseNodataChoice("-inf", "--nodata").value, -std::numeric_limits<double>::infinity());
}

TEST(NumberText, CommandLineRefusesTrailingText) {
    test::TempDir dir;
    test::writeFloatRaster(dir.file("h.tif"), 65, 65, test::syntheticHeights(65, 65));
    const auto r = run(programPath("preprocessDem") + " -q " + quoted(dir.file("h.tif")) + " --nodata -9999abc -o " +
                       quoted(dir.file("DEM.dat")));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.err, "preprocessDem: --nodata: '-9999abc' is not a number, nan, inf, -inf or none\n");
    EXPECT_FALSE(std::filesystem::exists(dir.file("DEM.dat")));
}

TEST(NumberText, DeclaredNodataTextIsReadWholeOrRefused) {
    test::TempDir dir;
    const std::vector<float> h = test::syntheticHeights(17, 17);
    test::GeoTiffTags tags;
    tags.gdalNodata = " -9999 "; // padded, as some writers do
    test::writeGeoTiff(dir.file("padded.tif"), 17, 17, h, tags);
    EXPECT_EQ(RasterSource::open(dir.file("padded.tif"))->info().nodata, -9999.0);
    tags.gdalNodata = "-9999abc";
    test::writeGeoTiff(dir.file("bad.tif"), 17, 17, h, tags);
    try {
        RasterSource::open(dir.file("bad.tif"));
        FAIL() << "GDAL_NODATA -9999abc read as a number";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("bad.tif"), std::string::npos) << what;
        EXPECT_NE(what.find("GDAL_NODATA '-9999abc' is not a number"), std::string::npos) << what;
    }
}

// A locale whose decimal separator is a comma, or empty when none can be had: an installed one,
// else one compiled with localedef into `dir` (LOCPATH).
std::string commaLocale(const test::TempDir& dir) {
    for (const char* name : {"de_DE.UTF-8", "fr_FR.UTF-8", "de_DE.utf8", "fr_FR.utf8"}) {
        if (std::setlocale(LC_NUMERIC, name)) {
            std::setlocale(LC_NUMERIC, "C");
            return name;
        }
    }
    const std::string command = "localedef -i de_DE -f UTF-8 " + quoted(dir.file("de_DE.UTF-8")) + " >/dev/null 2>&1";
    if (std::system(command.c_str()) != 0) {
        return "";
    }
    setenv("LOCPATH", dir.path().c_str(), 1);
    if (!std::setlocale(LC_NUMERIC, "de_DE.UTF-8")) {
        return "";
    }
    std::setlocale(LC_NUMERIC, "C");
    return "de_DE.UTF-8";
}

TEST(NumberText, TheLocaleDoesNotChangeNumbers) {
    test::TempDir dir;
    const std::string locale = commaLocale(dir);
    if (locale.empty()) {
        GTEST_SKIP() << "no locale with a decimal comma";
    }
    ASSERT_NE(std::setlocale(LC_NUMERIC, locale.c_str()), nullptr);
    EXPECT_STREQ(std::localeconv()->decimal_point, ",");
    EXPECT_EQ(std::strtod("0,5", nullptr), 0.5); // the C library does follow the locale
    EXPECT_EQ(tryParseNumber("0.5"), 0.5);
    EXPECT_FALSE(tryParseNumber("0,5").has_value());
    EXPECT_EQ(*tryParseNodataText("-9999.5"), -9999.5);
    EXPECT_EQ(*parseNodataChoice("-32767.25", "--nodata").value, -32767.25);
    EXPECT_THROW(parseNodataChoice("-32767,25", "--nodata"), Error);
    test::GeoTiffTags tags;
    tags.gdalNodata = "-9999.5";
    test::writeGeoTiff(dir.file("nd.tif"), 17, 17, test::syntheticHeights(17, 17), tags);
    EXPECT_EQ(RasterSource::open(dir.file("nd.tif"))->info().nodata, -9999.5);
    std::setlocale(LC_NUMERIC, "C");
}

} // namespace
} // namespace pyramid
