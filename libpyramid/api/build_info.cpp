#include "libpyramid/api/build_info.hpp"

#include <GeographicLib/Config.h>
#include <geotiff/geotiff.h>
#include <libdeflate.h>
#include <omp.h>
#include <png.h>
#include <tiffio.h>
#include <zlib.h>

#include "formats/error.hpp"
#include "libpyramid/input/geotiff_library.hpp"
#include "libpyramid/input/image_io_module.hpp"

namespace pyramid {

namespace {

// "LIBTIFF, Version 4.5.0\nCopyright ..." -> "4.5.0".
std::string tiffVersion() {
    const std::string text = TIFFGetVersion();
    const std::string key = "Version ";
    const size_t at = text.find(key);
    if (at == std::string::npos) {
        return text.substr(0, text.find('\n'));
    }
    const size_t from = at + key.size();
    return text.substr(from, text.find_first_of(" \n", from) - from);
}

// 1710 -> "1.7.1" (LIBGEOTIFF_VERSION: major, minor, patch and a last digit).
std::string geotiffHeaderVersion() {
    const int v = LIBGEOTIFF_VERSION;
    return std::to_string(v / 1000) + "." + std::to_string(v / 100 % 10) + "." + std::to_string(v / 10 % 10);
}

// The OpenMP specification the compiler implements: _OPENMP is its date.
std::string openmpVersion() {
    struct Spec {
        int date;
        const char* version;
    };
    static constexpr Spec kSpecs[] = {{200805, "3.0"}, {201107, "3.1"}, {201307, "4.0"}, {201511, "4.5"},
                                      {201811, "5.0"}, {202011, "5.1"}, {202111, "5.2"}};
    for (const Spec& s : kSpecs) {
        if (s.date == _OPENMP) {
            return std::string(s.version) + " (" + std::to_string(_OPENMP) + ")";
        }
    }
    return std::to_string(_OPENMP);
}

} // namespace

std::vector<ComponentVersion> libraryVersions() {
    std::vector<ComponentVersion> out;
    out.push_back({"libtiff", tiffVersion()});
    out.push_back({"libdeflate", LIBDEFLATE_VERSION_STRING});
    out.push_back({"zlib", zlibVersion()});
    const auto png = static_cast<int>(png_access_version_number()); // 10639 is 1.6.39
    out.push_back({"libpng", std::to_string(png / 10000) + "." + std::to_string(png / 100 % 100) + "." + std::to_string(png % 100)});
    out.push_back({"GeographicLib", GEOGRAPHICLIB_VERSION_STRING});
    std::string why;
    out.push_back({"libgeotiff", geoTiffLibrary(why) ? geotiffHeaderVersion() : "not loaded: " + why});
    try {
        out.push_back({"OpenImageIO", imageIoModule("OpenImageIO").version()});
    } catch (const Error& e) {
        // "OpenImageIO: needs OpenImageIO, but the image I/O module cannot be loaded (...)"
        const std::string text = e.what();
        const size_t from = text.find("the image I/O module");
        out.push_back({"OpenImageIO", "not loaded: " + (from == std::string::npos ? text : text.substr(from))});
    }
    out.push_back({"OpenMP", openmpVersion()});
    return out;
}

} // namespace pyramid
