// The libraries a program runs on, as they name their own versions (for `--version`): read at
// run time where the library offers it (libtiff, zlib, libpng, OpenImageIO through the image
// I/O module), else the version of the headers the build used (libdeflate, GeographicLib,
// libgeotiff, OpenMP).
#pragma once
#include <string>
#include <vector>

namespace pyramid {

struct ComponentVersion {
    std::string name;    // "libtiff"
    std::string version; // "4.5.0", or why there is none ("not loaded: ...")
};

// libtiff, libdeflate, zlib, libpng, GeographicLib, libgeotiff, OpenImageIO and OpenMP, in that
// order. The two libraries loaded on demand (libgeotiff, OpenImageIO's module) are loaded here
// when they can be; otherwise their entry says why not.
std::vector<ComponentVersion> libraryVersions();

} // namespace pyramid
