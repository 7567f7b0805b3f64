// What a GDAL VRT names (input_list.hpp, its rules for VRTs): the files of its plain sources,
// read from its XML (vrt_xml.hpp) and checked, every band's <SimpleSource> and <ComplexSource>
// taken as a whole file with its own values, anything else refused naming the VRT. A source that
// is itself a VRT is the caller's to expand (input_list.cpp).
#pragma once
#include <string>
#include <vector>

namespace pyramid {

// The files of the sources of the VRT at PATH (a regular file), in its bands' order,
// resolved against its directory where relativeToVRT="1". Throws Error naming WHERE.
std::vector<std::string> vrtSourceFiles(const std::string& path, const std::string& where);

} // namespace pyramid
