// Mosaics on the command line: a VRT over the tiles, a list file, a directory and a glob give the
// same bytes as the files named one by one; verify takes the mosaic as its source, with --extent
// and --crs as the build took them; a file without georeferencing and a missing one are refused
// by name, with nothing written; --priority last lets the last listed file win overlaps.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/geotiffs.hpp"
#include "tests/support/mosaic_cuts.hpp"
#include "tests/support/paths.hpp"

namespace pyramid {
namespace {

using test::bytesOf;
using test::cut;
using test::Grid;
using test::heightAt;

TEST(Mosaic, CommandLinesTakeListsDirectoriesAndVrts) {
    test::TempDir dir;
    std::filesystem::create_directories(dir.file("tiles"));
    const Grid g{7.0, 46.0, 1.0 / 64.0};
    const std::string whole = cut(dir, "whole.tif", g, 0, 0, 70, 50);
    cut(dir, "tiles/a.tif", g, 0, 0, 30, 50);
    cut(dir, "tiles/b.tif", g, 30, 0, 40, 50);
    {
        std::ofstream list(dir.file("list.txt"));
        list << "# the tiles\ntiles/b.tif\n\ntiles/a.tif\n";
        std::ofstream vrt(dir.file("tiles.vrt"));
        vrt << "<VRTDataset rasterXSize=\"70\" rasterYSize=\"50\">\n"
               "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n"
               "    <SimpleSource><SourceFilename relativeToVRT=\"1\">tiles/a.tif</SourceFilename>"
               "<SourceBand>1</SourceBand></SimpleSource>\n"
               "    <ComplexSource><SourceFilename relativeToVRT=\"1\">tiles/b.tif</SourceFilename>"
               "<SourceBand>1</SourceBand></ComplexSource>\n"
               "  </VRTRasterBand>\n</VRTDataset>\n";
    }
    const std::string dem = test::programPath("preprocessDem");
    const std::string common = " --tile-size 32 --root-tile-size 4 --scale 0.25 -q";
    ASSERT_EQ(test::run(dem + " " + whole + " -o " + dir.file("whole.dat") + common).exitCode, 0);
    const std::vector<std::string> ways = {
        dir.file("tiles/a.tif") + " " + dir.file("tiles/b.tif"),
        "--input-list " + dir.file("list.txt"),
        dir.file("tiles"),
        dir.file("tiles.vrt"),
        "'" + dir.file("tiles") + "/*.tif'",
    };
    const std::vector<uint8_t> expected = bytesOf(dir.file("whole.dat"));
    ASSERT_FALSE(expected.empty());
    for (size_t k = 0; k < ways.size(); ++k) {
        const std::string out = dir.file("way" + std::to_string(k) + ".dat");
        const test::RunResult r = test::run(dem + " " + ways[k] + " -o " + out + common + " --report -");
        ASSERT_EQ(r.exitCode, 0) << ways[k] << ": " << r.err;
        EXPECT_TRUE(bytesOf(out) == expected) << ways[k];
        EXPECT_NE(r.out.find("\"files\""), std::string::npos) << r.out;
    }
    // pyramid verify takes the mosaic as its source, as a VRT.
    const test::RunResult v = test::run(test::programPath("pyramid") + " verify " + dir.file("way0.dat") + " --source " +
                                        dir.file("tiles.vrt"));
    EXPECT_EQ(v.exitCode, 0) << v.out << v.err;
    // --extent on the file's grid: the tiles cut to a window; verify takes the same option, and
    // without it the window is not the source any more.
    const std::string window = " --extent 7.25,45.5,7.75,45.875";
    const test::RunResult e = test::run(dem + " " + ways[0] + " -o " + dir.file("window.dat") + common + window +
                                        " --report -");
    ASSERT_EQ(e.exitCode, 0) << e.err;
    EXPECT_NE(e.out.find("\"width\": 32"), std::string::npos) << e.out;
    EXPECT_NE(e.out.find("\"height\": 24"), std::string::npos) << e.out;
    const std::string verify = test::programPath("pyramid") + " verify " + dir.file("window.dat") + " --source " +
                               dir.file("tiles.vrt");
    EXPECT_EQ(test::run(verify + window).exitCode, 0);
    EXPECT_EQ(test::run(verify).exitCode, 1);
    // --crs into UTM: resampled, and verified against the same resampling.
    const std::string utm = " --crs EPSG:32632";
    const test::RunResult u = test::run(dem + " " + ways[0] + " -o " + dir.file("utm.dat") + common + utm + " --report -");
    ASSERT_EQ(u.exitCode, 0) << u.err;
    EXPECT_NE(u.out.find("\"epsg\": 32632"), std::string::npos) << u.out;
    EXPECT_EQ(test::run(verify.substr(0, verify.find(" verify ")) + " verify " + dir.file("utm.dat") + " --source " +
                        dir.file("tiles.vrt") + utm).exitCode, 0);
    const test::RunResult bad = test::run(dem + " " + ways[0] + " -o " + dir.file("bad.dat") + common + " --crs UTM32");
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("--crs: 'UTM32' is not a CRS"), std::string::npos) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.dat")));
    // Refusals name the file; nothing is written.
    const std::string plain = dir.file("plain.tif");
    test::writeGeoTiff(plain, 4, 4, std::vector<float>(16, 1.0f), test::GeoTiffTags{});
    const test::RunResult r1 = test::run(dem + " " + dir.file("tiles/a.tif") + " " + plain + " -o " + dir.file("x.dat") + common);
    EXPECT_EQ(r1.exitCode, 1);
    EXPECT_NE(r1.err.find("plain.tif: has no georeferencing"), std::string::npos) << r1.err;
    const test::RunResult r2 =
        test::run(dem + " " + dir.file("tiles/a.tif") + " " + dir.file("gone.tif") + " -o " + dir.file("x.dat") + common);
    EXPECT_EQ(r2.exitCode, 1);
    EXPECT_NE(r2.err.find("gone.tif"), std::string::npos) << r2.err;
    EXPECT_FALSE(test::fileExists(dir.file("x.dat")));
    const test::RunResult r3 = test::run(dem + " -o " + dir.file("x.dat") + common);
    EXPECT_EQ(r3.exitCode, 2) << r3.err;
}

TEST(Mosaic, PriorityLastLetsTheLastListedWin) {
    test::TempDir dir;
    // Two tiles overlapping by 10 columns with other heights there: which one wins shows.
    const Grid g{7.0, 46.0, 1.0 / 64.0};
    const std::string a = cut(dir, "a.tif", g, 0, 0, 40, 40);
    std::vector<float> v(40 * 40);
    for (int y = 0; y < 40; ++y) {
        for (int x = 0; x < 40; ++x) {
            v[static_cast<size_t>(x + y * 40)] = heightAt(30 + x, y) + 100.0f;
        }
    }
    const std::string b = dir.file("b.tif");
    test::writeGeoTiff(b, 40, 40, v, test::geographicTags(4326, 7.0 + 30.0 / 64.0, 46.0, 1.0 / 64.0));
    const std::string dem = test::programPath("preprocessDem");
    const std::string common = " --tile-size 32 --root-tile-size 4 --scale 0.25 -q -o ";
    ASSERT_EQ(test::run(dem + " " + a + " " + b + common + dir.file("ab.dat")).exitCode, 0);
    ASSERT_EQ(test::run(dem + " " + b + " " + a + common + dir.file("ba.dat")).exitCode, 0);
    ASSERT_EQ(test::run(dem + " " + a + " " + b + " --priority last" + common + dir.file("last.dat")).exitCode, 0);
    EXPECT_FALSE(bytesOf(dir.file("ab.dat")) == bytesOf(dir.file("ba.dat")));
    EXPECT_TRUE(bytesOf(dir.file("last.dat")) == bytesOf(dir.file("ba.dat")));
    EXPECT_EQ(test::run(dem + " " + a + " --priority middle" + common + dir.file("x.dat")).exitCode, 2);
}

} // namespace
} // namespace pyramid
