// The programs' libraries as a user meets them: TIFF and PNG inputs need no OpenImageIO (only a
// format that does fails, naming the file and the module), and --version names every library
// as it names itself at run time.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <png.h>
#include <tiffio.h>
#include <zlib.h>

#include "libpyramid/capi/pyramid.h"
#include "tests/support/paths.hpp"
#include "tests/support/rasters.hpp"

namespace pyramid {
namespace {

using test::lines;
using test::programPath;
using test::run;
using test::shellQuoted;

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

} // namespace
} // namespace pyramid
