// Gridded XYZ text (input/xyz_grid_reader.hpp): the window of samples/dem.tif written as XYZ
// lines, north first with spaces or south first with commas, CRLF and a header naming its
// columns in another order, reads back its heights, placed by its .prj as the GeoTIFF of them,
// and builds the GeoTIFF's pyramid; missing cells and `nan` heights are NaN, declared nodata; a
// file written again is scanned again (the scans are kept by path, size and time); a file that
// is no regular grid of rows is refused in one line naming the file and the line.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <functional>
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

std::string shortest(double v) {
    char text[32];
    const auto r = std::to_chars(text, text + sizeof text, v);
    return std::string(text, r.ptr);
}

// The window as XYZ lines: rows north first or south first, each line made by `line(x, y, z)`;
// cells for which `keep(column, row)` is false left out.
std::string windowXyz(const std::vector<float>& w, bool southFirst, const std::string& header,
                      const std::function<std::string(const std::string&, const std::string&, const std::string&)>& line,
                      const std::function<bool(int, int)>& keep = [](int, int) { return true; }) {
    std::string text = header;
    for (int k = 0; k < 65; ++k) {
        const int row = southFirst ? 64 - k : k;
        for (int column = 0; column < 65; ++column) {
            if (keep(column, row)) {
                text += line(shortest(500020.0 + 40.0 * column), shortest(5199980.0 - 40.0 * row),
                             shortest(w[static_cast<size_t>(row * 65 + column)]));
            }
        }
    }
    return text;
}

TEST(XyzGrid, RowsEitherWayReadAsTheirTiff) {
    const std::vector<float> window = test::gdalWindow();
    test::TempDir dir;
    test::writeGeoTiff(dir.file("window.tif"), 65, 65, window, test::projectedTags(32610, 500000.0, 5200000.0, 40.0));
    const DemEncodeOptions o = test::smallDemOptions();
    encodeDem(dir.file("window.tif"), dir.file("tif.dat"), o);
    const std::string prj = test::readFile(test::dataPath("gdal/window.prj"));
    test::writeText(dir.file("north.xyz"),
                    windowXyz(window, false, "", [](auto& x, auto& y, auto& z) { return x + " " + y + " " + z + "\n"; }));
    test::writeText(dir.file("south.XYZ"), windowXyz(window, true, "Height,Easting,Northing\r\n", [](auto& x, auto& y, auto& z) {
                        return z + "," + x + "," + y + "\r\n";
                    }));
    // Separators of every width, so that fields begin, end and run across the 16 and 64-byte
    // pieces the reader splits a line into.
    int k = 0;
    test::writeText(dir.file("padded.xyz"), windowXyz(window, false, "", [&k](auto& x, auto& y, auto& z) {
                        ++k;
                        return std::string(static_cast<size_t>(k % 70), ' ') + x + std::string(static_cast<size_t>(1 + k * 7 % 61), '\t') +
                               y + " ;," + std::string(static_cast<size_t>(k * 3 % 67), ' ') + z + std::string(static_cast<size_t>(k % 5), ';') + "\n";
                    }));
    for (const char* name : {"north.xyz", "south.XYZ", "padded.xyz"}) {
        SCOPED_TRACE(name);
        const std::string path = dir.file(name);
        test::writeText(path.substr(0, path.size() - 4) + ".prj", prj);
        const auto xyz = RasterSource::open(path);
        EXPECT_EQ(xyz->info().formatName, "xyz");
        EXPECT_FALSE(xyz->info().nodata);
        test::expectGdalWindow(*xyz, window);
        encodeDem(path, dir.file("xyz.dat"), o);
        EXPECT_EQ(test::readFile(dir.file("xyz.dat")), test::readFile(dir.file("tif.dat")));
        EXPECT_EQ(test::placementOf(dir.file("xyz.dat")), test::placementOf(dir.file("tif.dat")));
    }
}

TEST(XyzGrid, MissingCellsAndNanHeightsAreNodata) {
    const std::vector<float> window = test::gdalWindow();
    test::TempDir dir;
    // A coast: the cells west of a diagonal left out; the last row's first height written as nan.
    std::string text = windowXyz(
        window, false, "x\ty\tz\n", [](auto& x, auto& y, auto& z) { return x + "\t" + y + "\t" + z + "\n"; },
        [](int column, int row) { return column + row >= 20; });
    const size_t at = text.find("\t5197420\t") + 9;
    text.replace(at, text.find('\n', at) - at, "nan");
    test::writeText(dir.file("coast.xyz"), text);
    const auto xyz = RasterSource::open(dir.file("coast.xyz"));
    ASSERT_EQ(xyz->info().width, 65);
    ASSERT_EQ(xyz->info().height, 65);
    ASSERT_TRUE(xyz->info().nodata);
    EXPECT_TRUE(std::isnan(*xyz->info().nodata));
    std::vector<float> v(window.size());
    xyz->readFloat(0, 0, 65, 65, 0, v.data());
    for (int row = 0; row < 65; ++row) {
        for (int column = 0; column < 65; ++column) {
            const float got = v[static_cast<size_t>(row * 65 + column)];
            if (column + row < 20 || (row == 64 && column == 0)) {
                EXPECT_TRUE(std::isnan(got)) << column << " " << row;
            } else {
                EXPECT_EQ(got, window[static_cast<size_t>(row * 65 + column)]) << column << " " << row;
            }
        }
    }
    EXPECT_FALSE(xyz->info().georeference); // no .prj
}

TEST(XyzGrid, AFileWrittenAgainIsScannedAgain) {
    test::TempDir dir;
    const std::string p = dir.file("again.xyz");
    test::writeText(p, "0 1 1\n1 1 2\n2 1 3\n0 0 4\n1 0 5\n2 0 6\n");
    EXPECT_EQ(RasterSource::describe(p).width, 3);
    EXPECT_EQ(RasterSource::open(p)->info().width, 3);
    test::writeText(p, "0 1 1\n1 1 2\n0 0 4\n1 0 5\n");
    EXPECT_EQ(RasterSource::describe(p).width, 2);
    const auto xyz = RasterSource::open(p);
    std::vector<float> v(4);
    xyz->readFloat(0, 0, 2, 2, 0, v.data());
    EXPECT_EQ(v, (std::vector<float>{1, 2, 4, 5}));
}

TEST(XyzGrid, FilesThatAreNoGridOfRowsAreRefused) {
    test::TempDir dir;
    const std::string p = dir.file("x.xyz");
    const auto refusal = [&](const std::string& text) {
        test::writeText(p, text);
        EXPECT_THROW(RasterSource::describe(p), Error);
        return test::errorMessage([&] { RasterSource::open(p); });
    };
    EXPECT_EQ(refusal("0 0 1\n0 1 2\n1 0 3\n1 1 4\n"),
              p + ": is sorted by x (a column at a time): this reader takes rows, the lines of one y together with x "
                  "increasing (sort it by y, then x)");
    EXPECT_EQ(refusal("0 1 1\n1 1 2\n0 0 3\n1 0 4\n0 2 5\n1 2 6\n"),
              p + ": line 5: its y breaks the rows' order (the lines of one y together, the rows north to south or "
                  "south to north)");
    EXPECT_EQ(refusal("0 1 1\n2 1 2\n1 1 3\n"), p + ": line 3: its x does not increase along its row");
    EXPECT_EQ(refusal("x y z\n0 1 1\n1 1\n"), p + ": line 3 holds 2 fields, not the 3 of x, y and height");
    EXPECT_EQ(refusal("0 1 1\n1 one 2\n"), p + ": line 2: its y \"one\" is no number");
    EXPECT_EQ(refusal("0 1 1\n1 1 2\n0 0 3\n1 0 4\n0 -0.7 5\n1 -0.7 6\n"),
              p + ": line 3: its y lies off the grid of the rows' spacing 0.850000");
    EXPECT_EQ(refusal("0 0 1\n0.001 0 2\n1000 0 3\n"),
              p + ": its 3 points fill under 1/64 of the 1000001 x 1 cells their spacing makes: no regular grid");
    EXPECT_EQ(refusal("x y z\n5 5 5\n"), p + ": holds a single point: no grid");
    EXPECT_EQ(refusal("x y z\n"), p + ": holds no line of x, y and height");

    // Found as the rows are read: a point off the grid, a height that is no number or beyond float32.
    const auto readError = [&](const std::string& text) {
        test::writeText(p, text);
        const auto xyz = RasterSource::open(p);
        std::vector<float> v(static_cast<size_t>(xyz->info().width) * static_cast<size_t>(xyz->info().height));
        return test::errorMessage([&] { xyz->readFloat(0, 0, xyz->info().width, xyz->info().height, 0, v.data()); });
    };
    EXPECT_EQ(readError("0 1 1\n1 1 2\n2 1 3\n0 0 4\n1.3 0 5\n2 0 6\n"),
              p + ": line 2: its x lies off the grid of the spacing 0.666667");
    EXPECT_EQ(readError("0 1 1\n1 1 2\n0 0 high\n1 0 4\n"), p + ": line 3: its height \"high\" is no number");
    EXPECT_EQ(readError("0 1 1\n1 1 1e39\n"), p + ": line 2: its height lies beyond float32's range");
}

} // namespace
} // namespace pyramid
