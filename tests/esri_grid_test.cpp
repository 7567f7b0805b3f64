// ESRI's grids: ASCII grids (input/ascii_grid_reader.hpp) and .hdr-labelled raw grids
// (input/esri_grid_header.hpp, read by input/raw_grid_reader.hpp), as GDAL writes them and as
// their other writers do (ArcGIS's .flt, GTOPO30's .dem with its old-style .prj, any layout of
// bands). GDAL's files of a window of samples/dem.tif read back its samples and build the pyramid
// and placement of a GeoTIFF of them; a directory of ASCII tiles is a mosaic; files that do not
// hold what their header says are refused, naming the file and the place.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/input/input_list.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "tests/support/gdal_window.hpp"
#include "tests/support/geotiffs.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/sidecar_files.hpp"
#include "tests/support/small_dem.hpp"

namespace pyramid {
namespace {

std::vector<float> readAll(const RasterSource& source, int channel = 0) {
    const RasterInfo& info = source.info();
    std::vector<float> v(static_cast<size_t>(info.width) * static_cast<size_t>(info.height));
    source.readFloat(0, 0, info.width, info.height, channel, v.data());
    return v;
}

TEST(EsriGrid, GdalsAsciiGridAndBilReadAsTheirTiff) {
    // GDAL's window.asc (float32) and window-int16.bil (rounded to int16).
    const std::vector<float> window = test::gdalWindow();
    const auto asc = RasterSource::open(test::dataPath("gdal/window.asc"));
    EXPECT_EQ(asc->info().formatName, "aaigrid");
    EXPECT_EQ(asc->info().type, SampleType::Float32);
    EXPECT_EQ(readAll(*asc), window); // GDAL writes each float32 in full
    const auto bil = RasterSource::open(test::dataPath("gdal/window-int16.bil"));
    EXPECT_EQ(bil->info().formatName, "ehdr");
    EXPECT_EQ(bil->info().type, SampleType::Int16);
    EXPECT_EQ(readAll(*bil), test::gdalWindow(true));
    for (const RasterSource* s : {asc.get(), bil.get()}) {
        ASSERT_TRUE(s->info().georeference) << s->path();
        EXPECT_EQ(s->info().georeference->epsg, 32610); // ESRI's WKT in the .prj, identified by PROJ
        EXPECT_EQ(s->info().georeference->pixelToCrs, test::kGdalWindowPlace);
        EXPECT_EQ(RasterSource::describe(s->path()).georeference->pixelToCrs, test::kGdalWindowPlace);
    }

    // The pyramid and placement of a GeoTIFF of the same samples, byte for byte.
    test::TempDir dir;
    test::writeGeoTiff(dir.file("window.tif"), 65, 65, window, test::projectedTags(32610, 500000.0, 5200000.0, 40.0));
    DemEncodeOptions o = test::smallDemOptions();
    encodeDem(test::dataPath("gdal/window.asc"), dir.file("asc.dat"), o);
    encodeDem(dir.file("window.tif"), dir.file("tif.dat"), o);
    EXPECT_EQ(test::readFile(dir.file("asc.dat")), test::readFile(dir.file("tif.dat")));
    EXPECT_EQ(test::placementOf(dir.file("asc.dat")), test::placementOf(dir.file("tif.dat")));
}

TEST(EsriGrid, AsciiGridsAsTheirWritersLayThemOut) {
    test::TempDir dir;
    // Keywords in any case, the centre of the lower-left cell, values across lines as they
    // come (not one row a line), signs, exponents, CRLF, the nodata value.
    test::writeText(dir.file("a.asc"), "NCOLS 3\r\nNROWS 2\r\nXLLCENTER 10.5\r\nYLLCENTER 20.5\r\nCELLSIZE 1\r\n"
                                 "NODATA_VALUE -9999\r\n 1.5 +2 -3e2\r\n4 -9999\r\n 6.25\r\n");
    test::writeText(dir.file("a.prj"), "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
                                 "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433],AUTHORITY[\"EPSG\",\"4326\"]]");
    const auto a = RasterSource::open(dir.file("a.asc"));
    EXPECT_EQ(readAll(*a), (std::vector<float>{1.5f, 2.0f, -300.0f, 4.0f, -9999.0f, 6.25f}));
    EXPECT_EQ(a->info().nodata, -9999.0);
    ASSERT_TRUE(a->info().georeference);
    EXPECT_EQ(a->info().georeference->epsg, 4326);
    EXPECT_EQ(a->info().georeference->pixelToCrs, (std::array<double, 6>{10.0, 1.0, 0.0, 22.0, 0.0, -1.0}));
    // A .hdr of the same name beside it is another file's (a.bil's): the ASCII grid is read.
    test::writeText(dir.file("a.hdr"), "nrows 1\nncols 1\nnbits 16\n");
    EXPECT_EQ(readAll(*RasterSource::open(dir.file("a.asc")))[0], 1.5f);
    EXPECT_EQ(RasterSource::describe(dir.file("a.asc")).formatName, "aaigrid");
    // Without a .prj the grid is unplaced (as any file without a CRS).
    test::writeText(dir.file("b.asc"), "ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n7\n");
    EXPECT_FALSE(RasterSource::describe(dir.file("b.asc")).georeference);
    // The last value ends the file, with no line's end after it.
    test::writeText(dir.file("c.asc"), "ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 +2.5e1");
    EXPECT_EQ(readAll(*RasterSource::open(dir.file("c.asc"))), (std::vector<float>{1.0f, 25.0f}));

    // A grid larger than the cache budget is decoded into a scratch file: the same values.
    std::string text = "ncols 600\nnrows 600\nxllcorner 0\nyllcorner 0\ncellsize 30\n";
    std::vector<float> expected;
    for (int y = 0; y < 600; ++y) {
        for (int x = 0; x < 600; ++x) {
            const float v = static_cast<float>(x * 7 - y * 3) * 0.125f;
            expected.push_back(v);
            text += std::to_string(v) + (x == 599 ? "\n" : " ");
        }
    }
    test::writeText(dir.file("big.asc"), text);
    EXPECT_EQ(readAll(*RasterSource::open(dir.file("big.asc"), 1)), expected); // 1.4 MB > 1 MB
    EXPECT_EQ(readAll(*RasterSource::open(dir.file("big.asc"), 64)), expected);
}

TEST(EsriGrid, AsciiGridsThatDoNotHoldTheirHeadersValuesAreRefused) {
    test::TempDir dir;
    const std::string header = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
    const auto readError = [&](const std::string& name, const std::string& values) {
        test::writeText(dir.file(name), header + values);
        return test::errorMessage([&] { readAll(*RasterSource::open(dir.file(name))); });
    };
    EXPECT_EQ(readError("few.asc", "10 20 30\n40 50\n"),
              dir.file("few.asc") + ": ends after 5 of the 3 x 2 values its header gives");
    EXPECT_EQ(readError("more.asc", "1 2 3\n4 5 6\n7\n"),
              dir.file("more.asc") + ": holds more values than the 3 x 2 its header gives");
    EXPECT_EQ(readError("word.asc", "1 2 3\n4 x5 6\n"), dir.file("word.asc") + ": row 1, column 1: \"x5\" is not a number");
    EXPECT_EQ(readError("tail.asc", "1 2 3\n4 5x 6\n"), dir.file("tail.asc") + ": row 1, column 1: \"5x\" is not a number");
    EXPECT_EQ(readError("end.asc", "1 2 3\n4 5 6e"), dir.file("end.asc") + ": row 1, column 2: \"6e\" is not a number");
    EXPECT_EQ(readError("huge.asc", "1 2 3\n4 5 1e39\n"),
              dir.file("huge.asc") + ": row 1, column 2: \"1e39\" is beyond float32's range");
    // A header giving more values than its file's bytes can hold: refused at once, before a row
    // of 2^31 - 1 values is allocated.
    test::writeText(dir.file("wide.asc"), "ncols 2147483647\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n");
    EXPECT_EQ(test::errorMessage([&] { RasterSource::open(dir.file("wide.asc")); }),
              dir.file("wide.asc") + ": holds 66 bytes, too few for the 2147483647 x 1 values its header gives");
    test::writeText(dir.file("rows.asc"), "ncols 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n");
    EXPECT_EQ(test::errorMessage([&] { RasterSource::describe(dir.file("rows.asc")); }),
              dir.file("rows.asc") + ": an ASCII grid's header needs nrows, a whole number from 1");
    test::writeText(dir.file("cell.asc"), "ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize -1\n1\n");
    EXPECT_EQ(test::errorMessage([&] { RasterSource::describe(dir.file("cell.asc")); }),
              dir.file("cell.asc") + ": the cell size must be positive, not -1");
}

// 3 bands of 4 x 2 uint16 samples, band b pixel (x, y) = 1000 b + 10 y + x, in `layout`, big-endian.
std::vector<uint8_t> bands(const std::string& layout, size_t skip, size_t rowPadding) {
    std::vector<uint8_t> out(skip, 0xee);
    const auto put = [&](int b, int x, int y) {
        const int v = 1000 * b + 10 * y + x;
        out.push_back(static_cast<uint8_t>(v >> 8));
        out.push_back(static_cast<uint8_t>(v & 0xff));
    };
    if (layout == "BSQ") {
        for (int b = 0; b < 3; ++b) {
            for (int y = 0; y < 2; ++y) {
                for (int x = 0; x < 4; ++x) {
                    put(b, x, y);
                }
            }
        }
        return out;
    }
    for (int y = 0; y < 2; ++y) {
        for (int i = 0; i < 12; ++i) {
            layout == "BIL" ? put(i / 4, i % 4, y) : put(i % 3, i / 3, y);
        }
        out.insert(out.end(), rowPadding, 0xee);
    }
    return out;
}

TEST(EsriGrid, HdrGridsOfEveryLayoutAndWriter) {
    test::TempDir dir;
    std::vector<uint16_t> expected;
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 4; ++x) {
            for (int b = 0; b < 3; ++b) {
                expected.push_back(static_cast<uint16_t>(1000 * b + 10 * y + x));
            }
        }
    }
    for (const std::string layout : {"BIL", "BIP", "BSQ"}) {
        // No BYTEORDER: big-endian, as GDAL takes it; a header before the samples; padded rows.
        const std::string name = "i-" + layout;
        std::string hdr = "NROWS 2\nNCOLS 4\nNBANDS 3\nNBITS 16\nLAYOUT " + layout + "\nSKIPBYTES 6\n";
        if (layout != "BSQ") {
            hdr += "TOTALROWBYTES 30\n";
        }
        test::writeText(dir.file(name + ".hdr"), hdr);
        test::writeBytes(dir.file(name + ".bil"), bands(layout, 6, layout == "BSQ" ? 0 : 6));
        const auto s = RasterSource::open(dir.file(name + ".bil"));
        EXPECT_EQ(s->info().type, SampleType::UInt16) << layout;
        EXPECT_EQ(s->info().channels, 3) << layout;
        std::vector<uint16_t> v(expected.size());
        s->readUInt16(0, 0, 4, 2, 0, 3, v.data());
        EXPECT_EQ(v, expected) << layout;
        float f = 0.0f;
        s->readFloat(3, 1, 4, 2, 2, &f);
        EXPECT_EQ(f, 2013.0f) << layout;
    }

    // ArcGIS's float grid: .flt, byteorder LSBFIRST, the lower-left corner, its nodata.
    test::writeText(dir.file("f.hdr"), "ncols 2\nnrows 2\nxllcorner 300000\nyllcorner 4000000\ncellsize 10\n"
                                 "NODATA_value -9999\nbyteorder LSBFIRST\n");
    const std::vector<float> fv = {1.25f, -9999.0f, 3.5f, 1e-3f};
    std::vector<uint8_t> fb(16);
    std::memcpy(fb.data(), fv.data(), 16); // this machine's order is little-endian
    test::writeBytes(dir.file("f.flt"), fb);
    const auto f = RasterSource::open(dir.file("f.flt"));
    EXPECT_EQ(f->info().type, SampleType::Float32);
    EXPECT_EQ(readAll(*f), fv);
    EXPECT_EQ(f->info().nodata, -9999.0);

    // GTOPO30: NBITS 16 without PIXELTYPE and a negative NODATA (signed, as GDAL reads it), the
    // old-style .prj in capitals, the upper-left pixel's centre.
    test::writeText(dir.file("W140N40.HDR"), "BYTEORDER M\nLAYOUT BIL\nNROWS 2\nNCOLS 2\nNBANDS 1\nNBITS 16\n"
                                       "BANDROWBYTES 4\nTOTALROWBYTES 4\nBANDGAPBYTES 0\nNODATA -9999\n"
                                       "ULXMAP -139.99583333333334\nULYMAP 39.99583333333333\n"
                                       "XDIM 0.00833333333333\nYDIM 0.00833333333333\n");
    test::writeText(dir.file("W140N40.PRJ"), "Projection    GEOGRAPHIC\nDatum         WGS84\nZunits        METERS\n"
                                       "Units         DD\nSpheroid      WGS84\nXshift        0.0000000000\n"
                                       "Yshift        0.0000000000\nParameters\n");
    test::writeBytes(dir.file("W140N40.DEM"), {0xd8, 0xf1, 0x00, 0x10, 0x12, 0x34, 0xff, 0xfe});
    const auto g = RasterSource::open(dir.file("W140N40.DEM"));
    EXPECT_EQ(g->info().type, SampleType::Int16);
    EXPECT_EQ(readAll(*g), (std::vector<float>{-9999.0f, 16.0f, 4660.0f, -2.0f}));
    ASSERT_TRUE(g->info().georeference);
    EXPECT_EQ(g->info().georeference->epsg, 4326);
    EXPECT_DOUBLE_EQ(g->info().georeference->pixelToCrs[0], -140.0);
    EXPECT_DOUBLE_EQ(g->info().georeference->pixelToCrs[3], 40.0);

    // Old-style .prj of a UTM zone (NAD83) and of seconds of arc; no NBITS nor PIXELTYPE: the
    // type is the file's size per sample (4 bytes: float32, as GDAL guesses).
    test::writeText(dir.file("u.hdr"), "nrows 1\nncols 1\nbyteorder I\nulxmap 500005\nulymap 4000005\nxdim 10\nydim 10\n");
    test::writeText(dir.file("u.prj"), "Projection UTM\nZone 10\nDatum NAD83\nUnits METERS\nParameters\n");
    test::writeBytes(dir.file("u.bil"), {0x00, 0x00, 0x20, 0x41});
    const auto u = RasterSource::open(dir.file("u.bil"));
    EXPECT_EQ(u->info().type, SampleType::Float32);
    EXPECT_EQ(readAll(*u), std::vector<float>{10.0f});
    EXPECT_EQ(u->info().georeference->epsg, 26910);
    test::writeText(dir.file("s.hdr"), "nrows 1\nncols 1\nnbits 8\nulxmap 1800\nulymap 5400\nxdim 3600\nydim 3600\n");
    test::writeText(dir.file("s.prj"), "Projection GEOGRAPHIC\nDatum WGS84\nUnits DS\nParameters\n");
    test::writeBytes(dir.file("s.bil"), {7});
    EXPECT_EQ(RasterSource::describe(dir.file("s.bil")).georeference->pixelToCrs,
              (std::array<double, 6>{0.0, 1.0, 0.0, 2.0, 0.0, -1.0}));
}

TEST(EsriGrid, HdrGridsThatDoNotFitTheirDataAreRefused) {
    test::TempDir dir;
    test::writeText(dir.file("a.hdr"), "nrows 2\nncols 2\nnbits 16\n");
    test::writeBytes(dir.file("a.bil"), {1, 2, 3, 4, 5, 6});
    EXPECT_EQ(test::errorMessage([&] { RasterSource::open(dir.file("a.bil")); }),
              dir.file("a.bil") + ": holds 6 bytes, too few for 2 x 2 samples of 1 band(s) of uint16 as its header "
                                  "lays them out");
    test::writeText(dir.file("a.hdr"), "nrows 2\nncols 2\nnbits 4\n");
    EXPECT_EQ(test::errorMessage([&] { RasterSource::open(dir.file("a.bil")); }),
              dir.file("a.hdr") + ": NBITS 4 with PIXELTYPE unset: samples of 8, 16 or 32 bits (64 for floats) are read");
    test::writeText(dir.file("a.hdr"), "nrows 2\nncols 2\nlayout BIX\n");
    EXPECT_EQ(test::errorMessage([&] { RasterSource::open(dir.file("a.bil")); }),
              dir.file("a.hdr") + ": LAYOUT BIX: BIL, BIP or BSQ are read");
    test::writeText(dir.file("a.hdr"), "nrows 2\nncols 2.5\n");
    EXPECT_EQ(test::errorMessage([&] { RasterSource::open(dir.file("a.bil")); }),
              dir.file("a.hdr") + ": ncols must be a whole number from 1, not 2.5");
    // Heights are no colours.
    test::writeText(dir.file("a.hdr"), "nrows 1\nncols 1\nnbits 16\npixeltype signedint\n");
    std::vector<uint16_t> v(1);
    EXPECT_EQ(test::errorMessage([&] { RasterSource::open(dir.file("a.bil"))->readUInt16(0, 0, 1, 1, 0, 1, v.data()); }),
              dir.file("a.bil") + ": holds int16 samples, not 8 or 16-bit colours");
}

TEST(EsriGrid, ADirectoryOfAsciiTilesIsAMosaic) {
    test::TempDir dir;
    // Two 3 x 2 tiles side by side, on one 1 m grid.
    test::writeText(dir.file("w.asc"), "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n");
    test::writeText(dir.file("e.asc"), "ncols 3\nnrows 2\nxllcorner 3\nyllcorner 0\ncellsize 1\n7 8 9\n10 11 12\n");
    const std::string prj = "PROJCS[\"WGS 84 / UTM zone 10N\",GEOGCS[\"WGS 84\"],AUTHORITY[\"EPSG\",\"32610\"]]";
    test::writeText(dir.file("w.prj"), prj);
    test::writeText(dir.file("e.prj"), prj);
    const InputList inputs = expandInputs({dir.path()});
    ASSERT_EQ(inputs.paths.size(), 2u);
    const auto mosaic = RasterSource::openMosaic(inputs.paths);
    EXPECT_EQ(mosaic->info().width, 6);
    EXPECT_EQ(readAll(*mosaic), (std::vector<float>{1, 2, 3, 7, 8, 9, 4, 5, 6, 10, 11, 12}));
}

} // namespace
} // namespace pyramid
