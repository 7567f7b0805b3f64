// Files the tests write beside a raster (headers, sidecars, raw samples), and what a planar
// pyramid's georeference sidecar says of its placement.
#pragma once
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/paths.hpp"

namespace pyramid::test {

inline void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

inline void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                static_cast<std::streamsize>(bytes.size()));
}

// The georeference sidecar of the pyramid `pyramidPath` without the pyramid's own name: two
// builds placed alike compare equal.
inline nlohmann::json placementOf(const std::string& pyramidPath) {
    nlohmann::json j = nlohmann::json::parse(readFile(pyramidPath + ".georef.json"));
    j.erase("pyramid");
    return j;
}

} // namespace pyramid::test
