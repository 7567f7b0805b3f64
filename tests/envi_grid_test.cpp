// ENVI's raw rasters (input/envi_header.hpp, read by input/raw_grid_reader.hpp): GDAL's file of a
// window of samples/dem.tif reads back its samples where its header places them; the header's
// other forms (a name with ".hdr" appended, big-endian bands interleaved by line or pixel, a map
// info without a WKT) read as their writers meant; headers naming what is not read are refused,
// naming the header.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/gdal_window.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sidecar_files.hpp"

namespace pyramid {
namespace {

TEST(EnviGrid, GdalsEnviFileReadsAsItsTiff) {
    const std::vector<float> window = test::gdalWindow(true); // GDAL's -ot Int16
    const auto envi = RasterSource::open(test::dataPath("gdal/window-envi.img"));
    EXPECT_EQ(envi->info().formatName, "envi");
    EXPECT_EQ(envi->info().type, SampleType::Int16);
    test::expectGdalWindow(*envi, window);
}

TEST(EnviGrid, HeadersOfOtherWriters) {
    test::TempDir dir;
    // PATH.hdr beside a data file, big-endian uint16 bands interleaved by line after a header
    // of 4 bytes, the reference pixel at the first pixel's centre (1.5, 1.5), a map info of its
    // own CRS (UTM zone 10 South), the nodata value.
    test::writeText(dir.file("x.dat.hdr"), "ENVI\ndescription = {two\n  lines}\nsamples = 2\nlines = 1\nbands = 2\n"
                                     "header offset = 4\ndata type = 12\ninterleave = bil\nbyte order = 1\n"
                                     "map info = {UTM, 1.5, 1.5, 300015, 7000015, 30, 30, 10, South, WGS-84, units=Meters}\n"
                                     "data ignore value = 65535\n");
    test::writeBytes(dir.file("x.dat"), {9, 9, 9, 9, 0x01, 0x02, 0xff, 0xff, 0x00, 0x07, 0x00, 0x08});
    const auto x = RasterSource::open(dir.file("x.dat"));
    EXPECT_EQ(x->info().type, SampleType::UInt16);
    std::vector<uint16_t> v(4);
    x->readUInt16(0, 0, 2, 1, 0, 2, v.data());
    EXPECT_EQ(v, (std::vector<uint16_t>{0x0102, 7, 0xffff, 8}));
    EXPECT_EQ(x->info().nodata, 65535.0);
    ASSERT_TRUE(x->info().georeference);
    EXPECT_EQ(x->info().georeference->epsg, 32710);
    EXPECT_EQ(x->info().georeference->pixelToCrs, (std::array<double, 6>{300000.0, 30.0, 0.0, 7000030.0, 0.0, -30.0}));

    // Bands interleaved by pixel, float32 little-endian; no map info: unplaced.
    test::writeText(dir.file("p.hdr"), "ENVI\nsamples = 2\nlines = 1\nbands = 2\ndata type = 4\ninterleave = bip\n");
    test::writeBytes(dir.file("p.img"), {0, 0, 0x80, 0x3f, 0, 0, 0, 0x40, 0, 0, 0x40, 0x40, 0, 0, 0x80, 0x40});
    const auto p = RasterSource::open(dir.file("p.img"));
    float second[2] = {};
    p->readFloat(0, 0, 2, 1, 1, second);
    EXPECT_EQ(second[0], 2.0f);
    EXPECT_EQ(second[1], 4.0f);
    EXPECT_FALSE(p->info().georeference);
}

TEST(EnviGrid, HeadersNamingWhatIsNotReadAreRefused) {
    test::TempDir dir;
    test::writeBytes(dir.file("a.img"), std::vector<uint8_t>(64, 0));
    const auto refusal = [&](const std::string& header) {
        test::writeText(dir.file("a.hdr"), "ENVI\n" + header);
        return test::errorMessage([&] { RasterSource::open(dir.file("a.img")); });
    };
    const std::string where = dir.file("a.hdr") + ": ";
    EXPECT_EQ(refusal("lines = 2\ndata type = 1\n"), where + "an ENVI header needs \"samples\"");
    EXPECT_EQ(refusal("samples = 2\nlines = 2\ndata type = 6\n"),
              where + "data type = 6: 1, 2, 3, 4, 5, 12 and 13 are read (complex and 64-bit integer samples are not)");
    EXPECT_EQ(refusal("samples = 2\nlines = 2\ndata type = 1\ninterleave = bxq\n"),
              where + "interleave = bxq: bsq, bil or bip are read");
    EXPECT_EQ(refusal("samples = 2\nlines = 2\ndata type = 1\nmap info = {UTM, 1, 1, 0, 0, 1, 1, 10, North, WGS-84, "
                      "rotation=30}\n"),
              where + "map info's rotation is not read: give the raster unrotated");
    // A braced value across lines is quoted on one line.
    EXPECT_EQ(refusal("samples = 2\nlines = 2\ndata type = 1\nmap info = {UTM, 1, 1,\n x, 0, 1, 1}\n"),
              where + "map info = {UTM, 1, 1,  x, 0, 1, 1}: items 2 to 7 must be numbers");
    EXPECT_EQ(refusal("samples = 16\nlines = 2\nbands = 3\ndata type = 2\n"),
              dir.file("a.img") + ": holds 64 bytes, too few for 16 x 2 samples of 3 band(s) of int16 as its header "
                                  "lays them out");
}

} // namespace
} // namespace pyramid
