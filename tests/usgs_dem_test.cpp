// USGS DEMs (input/usgs_dem_reader.hpp): GDAL's files of the window of samples/dem.tif (UTM, its
// profiles 1024-byte records) and of Mt Rainier's cell at DTED level 0's posts (geographic, in
// seconds of arc) read back their samples and placement and build their GeoTIFFs' pyramids; a
// file written a number a line, whose profiles start and end at different rows, with voids,
// numbers run into each other, feet and a southern zone, reads as the standard lays it out; a
// GTOPO30 `.dem` is still a raw grid; damaged files are refused in one line naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/gdal_window.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sidecar_files.hpp"
#include "tests/support/small_dem.hpp"

namespace pyramid {
namespace {

std::vector<float> readAll(const RasterSource& s) {
    std::vector<float> v(static_cast<size_t>(s.info().width) * static_cast<size_t>(s.info().height));
    s.readFloat(0, 0, s.info().width, s.info().height, 0, v.data());
    return v;
}

TEST(UsgsDem, GdalsFilesReadAsTheirTiff) {
    const std::vector<float> window = test::gdalWindow(true); // GDAL's -ot Int16
    test::TempDir dir;
    test::writeGeoTiff(dir.file("window.tif"), 65, 65, window, test::projectedTags(32610, 500000.0, 5200000.0, 40.0));
    const DemEncodeOptions o = test::smallDemOptions();
    encodeDem(dir.file("window.tif"), dir.file("tif.dat"), o);
    const std::string path = test::dataPath("gdal/window-i16.dem");
    const auto dem = RasterSource::open(path);
    EXPECT_EQ(dem->info().formatName, "usgsdem");
    EXPECT_EQ(dem->info().type, SampleType::Float32);
    ASSERT_TRUE(dem->info().nodata);
    EXPECT_TRUE(std::isnan(*dem->info().nodata));
    test::expectGdalWindow(*dem, window);
    encodeDem(path, dir.file("dem.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("dem.dat")), test::readFile(dir.file("tif.dat")));
    EXPECT_EQ(test::placementOf(dir.file("dem.dat")), test::placementOf(dir.file("tif.dat")));

    // Geographic: the profiles' coordinates in seconds of arc, on WGS 84.
    const auto n46 = RasterSource::open(test::dataPath("gdal/n46.dem"));
    const auto tif = RasterSource::open(test::dataPath("gdal/n46-dt0.tif"));
    ASSERT_EQ(n46->info().width, 121);
    ASSERT_EQ(n46->info().height, 121);
    EXPECT_EQ(readAll(*n46), readAll(*tif));
    ASSERT_TRUE(n46->info().georeference);
    EXPECT_EQ(n46->info().georeference->epsg, 4326);
    const std::array<double, 6> geo = {-122.0 - 1.0 / 240, 1.0 / 120, 0.0, 47.0 + 1.0 / 240, 0.0, -1.0 / 120};
    for (size_t k = 0; k < 6; ++k) {
        EXPECT_NEAR(n46->info().georeference->pixelToCrs[k], geo[k], 1e-12) << k;
    }
}

// A field of the A record: `text` right-aligned in bytes [first, last] (1-based).
void put(std::string& a, size_t first, size_t last, const std::string& text) {
    a.replace(last - text.size(), text.size(), text);
    (void)first;
}

// An A record: UTM zone `zone` (negative: south) on horizontal datum `datum`, elevations in
// `unit` (1 feet, 2 metres), posts 30 m apart, elevations in tenths, `profiles` profiles.
std::string aRecord(int zone, int datum, int unit, int profiles) {
    std::string a(1024, ' ');
    put(a, 1, 40, "handmade");
    put(a, 145, 150, "1");
    put(a, 151, 156, "1");
    put(a, 157, 162, "1");
    put(a, 163, 168, std::to_string(zone));
    put(a, 529, 534, "2");
    put(a, 535, 540, std::to_string(unit));
    put(a, 541, 546, "4");
    put(a, 817, 828, "3.000000D+01");
    put(a, 829, 840, "3.000000D+01");
    put(a, 841, 852, "1.000000E-01");
    put(a, 853, 858, "1");
    put(a, 859, 864, std::to_string(profiles));
    put(a, 891, 892, std::to_string(datum));
    return a;
}

// A profile written a number a line: its header, then `elevations` as they are given.
std::string profile(int column, int count, double x, double y, const std::string& elevations) {
    return "1\n" + std::to_string(column) + "\n" + std::to_string(count) + "\n1\n" + std::to_string(x) + "D+00\n" +
           std::to_string(y) + "\n100.0\n0.0\n0.0\n" + elevations + "\n";
}

TEST(UsgsDem, ProfilesOfEveryStartVoidsAndFeet) {
    test::TempDir dir;
    // Three profiles: from the middle row up two posts, from the south row up three (two voids
    // run into each other, then 7), and the north row alone, a void.
    const std::string text = aRecord(-33, 3, 1, 3) + profile(1, 2, 300000.0, 6000030.0, "5 -6") +
                             profile(2, 3, 300030.0, 6000000.0, "-32767-32767     7") +
                             profile(3, 1, 300060.0, 6000060.0, "-32767");
    test::writeText(dir.file("quad.DEM"), text);
    const auto dem = RasterSource::open(dir.file("quad.DEM"));
    ASSERT_EQ(dem->info().width, 3);
    ASSERT_EQ(dem->info().height, 3);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // The elevations in feet as stored (100 + 0.1 v), read in metres (the ground's unit).
    const std::vector<float> feet = {99.4f, 100.7f, nan, 100.5f, nan, nan, nan, nan, nan};
    const std::vector<float> got = readAll(*dem);
    for (size_t k = 0; k < feet.size(); ++k) {
        const auto metres = static_cast<float>(static_cast<double>(feet[k]) * 0.3048);
        EXPECT_TRUE(std::isnan(feet[k]) ? std::isnan(got[k]) : got[k] == metres) << k << ": " << got[k];
    }
    const auto& g = dem->info().georeference;
    ASSERT_TRUE(g);
    EXPECT_EQ(g->epsg, 32733); // WGS 84 / UTM zone 33S
    EXPECT_EQ(g->pixelToCrs, (std::array<double, 6>{299985.0, 30.0, 0.0, 6000075.0, 0.0, -30.0}));
    ASSERT_TRUE(g->heightUnit);
    EXPECT_EQ(g->heightUnit->metres, 0.3048);

    // No horizontal datum given (older files): unplaced, left to the sidecars.
    test::writeText(dir.file("old.dem"), aRecord(10, 0, 2, 3) + text.substr(1024));
    EXPECT_FALSE(RasterSource::describe(dir.file("old.dem")).georeference);
}

TEST(UsgsDem, AGtopo30DemIsStillARawGrid) {
    test::TempDir dir;
    test::writeText(dir.file("gt.hdr"), "BYTEORDER M\nLAYOUT BIL\nNROWS 2\nNCOLS 2\nNBANDS 1\nNBITS 16\nULXMAP 0.5\nULYMAP 1.5\n"
                                        "XDIM 1\nYDIM 1\n");
    test::writeBytes(dir.file("gt.dem"), {0, 1, 0, 2, 0, 3, 0, 4});
    const auto grid = RasterSource::open(dir.file("gt.dem"));
    EXPECT_NE(grid->info().formatName, "usgsdem");
    EXPECT_EQ(readAll(*grid), (std::vector<float>{1, 2, 3, 4}));
}

TEST(UsgsDem, DamagedFilesAreRefused) {
    test::TempDir dir;
    const std::string a = aRecord(10, 3, 2, 2);
    const std::string one = profile(1, 2, 300000.0, 6000030.0, "5 6");
    const auto refusal = [&](const std::string& text) {
        const std::string p = dir.file("x.dem");
        test::writeText(p, text);
        const std::string e = test::errorMessage([&] { RasterSource::open(p); });
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
        return e;
    };
    const std::string p = dir.file("x.dem");
    EXPECT_EQ(refusal(a + one + profile(2, 2, 300030.0, 6000030.0, "5")),
              p + ": ends before an elevation: a file cut short");
    const std::string word = a + one + profile(2, 2, 300030.0, 6000030.0, "5 x6");
    EXPECT_EQ(refusal(word), p + ": an elevation at byte " + std::to_string(word.find("x6")) + ": \"x6\" is no number");
    EXPECT_EQ(refusal(a + one + profile(3, 2, 300030.0, 6000030.0, "5 6")),
              p + ": profile 2 is numbered column 3 (row 1, 2 x 1 elevations): the profiles are one column each, "
                  "numbered 1, 2, ... in turn");
    EXPECT_EQ(refusal(a + one + profile(2, 2, 300045.0, 6000030.0, "5 6")),
              p + ": profile 2 starts off the grid of its resolution, or not east of the one before");
    EXPECT_EQ(refusal(a + one + profile(2, 2, 3000000.0, 6000030.0, "5 6")),
              p + ": its profiles span 90001 x 2 posts of its resolution, which its 4 elevations do not fill");
}

} // namespace
} // namespace pyramid
