// DTED files (input/dted_reader.hpp): GDAL's level 0 file of Mt Rainier's cell reads back the
// samples and placement of the GeoTIFF it was written from, and builds its pyramid byte for byte;
// files laid out by hand read as MIL-PRF-89020B lays them out (tape labels, sign and magnitude,
// voids, two's complement written by mistake, WGS 72, wider columns, bands of rows through the
// scratch file); damaged files are refused, naming the file and the column.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sidecar_files.hpp"
#include "tests/support/small_dem.hpp"

namespace pyramid {
namespace {

std::vector<float> readAll(const RasterSource& source) {
    const RasterInfo& info = source.info();
    std::vector<float> v(static_cast<size_t>(info.width) * static_cast<size_t>(info.height));
    source.readFloat(0, 0, info.width, info.height, 0, v.data());
    return v;
}

TEST(Dted, GdalsLevel0FileReadsAsItsTiff) {
    const auto dted = RasterSource::open(test::dataPath("gdal/n46.dt0"));
    const auto tiff = RasterSource::open(test::dataPath("gdal/n46-dt0.tif"));
    const RasterInfo& info = dted->info();
    EXPECT_EQ(info.formatName, "dted");
    EXPECT_EQ(info.type, SampleType::Int16);
    EXPECT_EQ(info.width, 121);
    EXPECT_EQ(info.height, 121);
    EXPECT_EQ(info.nodata, -32767.0);
    EXPECT_EQ(readAll(*dted), readAll(*tiff));
    ASSERT_TRUE(info.georeference);
    EXPECT_EQ(info.georeference->epsg, 4326);
    EXPECT_TRUE(info.georeference->pixelIsPoint);
    ASSERT_TRUE(info.georeference->heightUnit);
    EXPECT_EQ(info.georeference->heightUnit->metres, 1.0);
    // Posts every 30" from (122 W, 46 N): pixel corners half a post outside.
    const std::array<double, 6> expected = {-122.0 - 1.0 / 240, 1.0 / 120, 0.0, 47.0 + 1.0 / 240, 0.0, -1.0 / 120};
    for (size_t k = 0; k < 6; ++k) {
        EXPECT_NEAR(info.georeference->pixelToCrs[k], expected[k], 1e-12) << k;
        EXPECT_NEAR(info.georeference->pixelToCrs[k], tiff->info().georeference->pixelToCrs[k], 1e-12) << k;
    }
    EXPECT_EQ(RasterSource::describe(test::dataPath("gdal/n46.dt0")).width, 121);

    // The GeoTIFF's pyramid, byte for byte.
    test::TempDir dir;
    DemEncodeOptions o = test::smallDemOptions();
    encodeDem(test::dataPath("gdal/n46.dt0"), dir.file("dted.dat"), o);
    encodeDem(test::dataPath("gdal/n46-dt0.tif"), dir.file("tif.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("dted.dat")), test::readFile(dir.file("tif.dat")));
}

// A DTED file as MIL-PRF-89020B lays it out: `width` records of `height` heights, south first,
// each the raw 16-bit word `word(x, j)` (j counted from the south).
struct DtedLayout {
    std::string longitude = "0340000E", latitude = "0120000S";
    std::string intervals = "00600030"; // 6" east to west, 3" south to north
    int width = 3, height = 4;
    std::string datum = "WGS84";
    bool tapeLabels = false;
};

std::vector<uint8_t> dtedBytes(const DtedLayout& l, const std::function<uint16_t(int, int)>& word) {
    std::string head;
    if (l.tapeLabels) {
        head += "VOL1" + std::string(76, ' ') + "HDR1" + std::string(76, ' ');
    }
    char counts[9];
    std::snprintf(counts, sizeof counts, "%04d%04d", l.width, l.height);
    std::string uhl = "UHL1" + l.longitude + l.latitude + l.intervals + "NA  U  " + std::string(12, ' ') + counts;
    uhl.resize(80, '0');
    std::string dsi = "DSIU" + std::string(644, ' ');
    dsi.replace(144, 5, l.datum);
    std::string acc = "ACC" + std::string(2697, ' ');
    head += uhl + dsi + acc;
    std::vector<uint8_t> bytes(head.begin(), head.end());
    for (int x = 0; x < l.width; ++x) {
        // The sentinel, the block count (3 bytes), the longitude count, the latitude count.
        std::vector<uint8_t> r = {0xAA, static_cast<uint8_t>(x >> 16), static_cast<uint8_t>(x >> 8), static_cast<uint8_t>(x),
                                  static_cast<uint8_t>(x >> 8), static_cast<uint8_t>(x), 0, 0};
        for (int j = 0; j < l.height; ++j) {
            const uint16_t w = word(x, j);
            r.push_back(static_cast<uint8_t>(w >> 8));
            r.push_back(static_cast<uint8_t>(w));
        }
        uint32_t sum = 0;
        for (const uint8_t b : r) {
            sum += b;
        }
        for (const int shift : {24, 16, 8, 0}) {
            r.push_back(static_cast<uint8_t>(sum >> shift));
        }
        bytes.insert(bytes.end(), r.begin(), r.end());
    }
    return bytes;
}

std::string errorOpening(const std::string& path) {
    try {
        const auto source = RasterSource::open(path);
        readAll(*source);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Dted, FilesAsTheStandardLaysThemOut) {
    test::TempDir dir;
    // Columns west to east, heights south to north as sign and magnitude: 7, -5, a void, and
    // -3 written in two's complement by mistake (0xfffd), read as GDAL reads it.
    const std::vector<std::vector<uint16_t>> columns = {
        {7, 0x8005, 0xffff, 0xfffd}, {0, 0x8000, 0x7fff, 100}, {1, 2, 3, 0x8000 | 16000}};
    DtedLayout l;
    l.tapeLabels = true;
    l.datum = "WGS72";
    test::writeBytes(dir.file("s12e034.dt1"), dtedBytes(l, [&](int x, int j) { return columns[x][j]; }));
    const auto s = RasterSource::open(dir.file("s12e034.dt1"));
    EXPECT_EQ(s->info().width, 3);
    EXPECT_EQ(s->info().height, 4);
    // Rows north first.
    EXPECT_EQ(readAll(*s), (std::vector<float>{-3, 100, -16000, -32767, 32767, 3, -5, 0, 2, 7, 0, 1}));
    ASSERT_TRUE(s->info().georeference);
    EXPECT_EQ(s->info().georeference->epsg, 4322); // WGS 72
    const double dx = 6.0 / 3600, dy = 3.0 / 3600;
    const std::array<double, 6> t = s->info().georeference->pixelToCrs;
    EXPECT_NEAR(t[0], 34.0 - dx / 2, 1e-12);
    EXPECT_NEAR(t[1], dx, 1e-15);
    EXPECT_NEAR(t[3], -12.0 + 3 * dy + dy / 2, 1e-12);
    EXPECT_NEAR(t[5], -dy, 1e-15);
    EXPECT_EQ(RasterSource::describe(dir.file("s12e034.dt1")).formatName, "dted");

    // Minutes and seconds of origin; the name does not matter.
    l = DtedLayout{};
    l.longitude = "1223015W";
    l.latitude = "0460045N";
    test::writeBytes(dir.file("cell"), dtedBytes(l, [](int x, int j) { return static_cast<uint16_t>(x + 10 * j); }));
    const auto c = RasterSource::open(dir.file("cell"));
    EXPECT_EQ(c->info().georeference->epsg, 4326);
    EXPECT_NEAR(c->info().georeference->pixelToCrs[0], -(122.0 + 30.0 / 60 + 15.0 / 3600) - dx / 2, 1e-12);
    EXPECT_NEAR(c->info().georeference->pixelToCrs[3], 46.0 + 45.0 / 3600 + 3 * dy + dy / 2, 1e-12);
    EXPECT_EQ(readAll(*c), (std::vector<float>{30, 31, 32, 20, 21, 22, 10, 11, 12, 0, 1, 2}));
}

TEST(Dted, BandsOfRowsAndTheScratchFile) {
    // 1400 columns: bands of 1498 rows (4 MB), so 3100 rows are three bands; a cache of 1 MB
    // puts the rows into a scratch file.
    test::TempDir dir;
    DtedLayout l;
    l.width = 1400;
    l.height = 3100;
    const auto height = [](int x, int j) { return (x * 7 + j * 13) % 9000 - 500; };
    test::writeBytes(dir.file("big.dt2"), dtedBytes(l, [&](int x, int j) {
                         const int h = height(x, j);
                         return static_cast<uint16_t>(h < 0 ? 0x8000 | -h : h);
                     }));
    const auto big = RasterSource::open(dir.file("big.dt2"), 1);
    const std::vector<float> v = readAll(*big);
    size_t wrong = 0;
    for (int y = 0; y < l.height; ++y) {
        for (int x = 0; x < l.width; ++x) {
            wrong += v[static_cast<size_t>(y) * 1400 + static_cast<size_t>(x)] != height(x, l.height - 1 - y);
        }
    }
    EXPECT_EQ(wrong, 0u);
}

TEST(Dted, DamagedFilesAreRefused) {
    test::TempDir dir;
    const auto word = [](int x, int j) { return static_cast<uint16_t>(x * 4 + j); };
    const std::vector<uint8_t> good = dtedBytes(DtedLayout{}, word);
    const std::string path = dir.file("x.dt0");
    const auto refusal = [&](const std::vector<uint8_t>& bytes) {
        test::writeBytes(path, bytes);
        return errorOpening(path);
    };
    EXPECT_EQ(refusal(good), "");

    std::vector<uint8_t> cut(good.begin(), good.end() - 1);
    EXPECT_EQ(refusal(cut), path + ": holds 3487 bytes, too few for the 3 columns of 4 heights its UHL record gives "
                                   "(3488 bytes)");
    std::vector<uint8_t> damaged = good;
    damaged[3428 + 20 + 9] ^= 1; // a height of column 1
    EXPECT_EQ(refusal(damaged), path + ": column 1's checksum does not match its record's bytes: a damaged file");
    damaged = good;
    damaged[3428 + 2 * 20] = 0x55; // column 2's sentinel
    EXPECT_EQ(refusal(damaged), path + ": column 2's record does not begin as DTED's records do (sentinel 0xAA, "
                                       "column 2): a damaged file, or one whose UHL counts are wrong");

    DtedLayout l;
    l.datum = "NAD27";
    EXPECT_EQ(refusal(dtedBytes(l, word)),
              path + ": its DSI record's horizontal datum \"NAD27\" is neither WGS84 nor WGS72");
    l = DtedLayout{};
    l.longitude = "0346000E";
    EXPECT_EQ(refusal(dtedBytes(l, word)),
              path + ": its UHL record's longitude of origin \"0346000E\" is not DDDMMSS and E or W");
    l.longitude = "034\n000\xe9";
    EXPECT_EQ(refusal(dtedBytes(l, word)), // the file's bytes quoted printably: one line
              path + ": its UHL record's longitude of origin \"034\\x0a000\\xe9\" is not DDDMMSS and E or W");
    l = DtedLayout{};
    l.intervals = "0000NA  ";
    EXPECT_EQ(refusal(dtedBytes(l, word)),
              path + ": its UHL record's intervals \"0000NA  \" are not two numbers of tenths of a second from 1");
    std::vector<uint8_t> noDsi = good;
    noDsi[80] = 'X';
    EXPECT_EQ(refusal(noDsi),
              path + ": a DTED file's UHL record must be followed by its DSI and ACC records (648 and 2700 bytes)");
    // Not a DTED file at all: another reader's refusal.
    std::vector<uint8_t> other = good;
    other[0] = 'X';
    EXPECT_NE(refusal(other).find(path + ": "), std::string::npos);
    EXPECT_EQ(refusal(other).find("DTED"), std::string::npos);
}

} // namespace
} // namespace pyramid
