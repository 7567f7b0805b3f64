// Previews and tiles drawn as PNGs in the tests: a PNG's pixels and text as written, and the DEM
// pyramids they are drawn from.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "tests/support/paths.hpp"

namespace pyramid::test {

struct Png {
    int width = 0, height = 0, channels = 0, depth = 0;
    std::map<std::string, std::string> text;
    std::vector<uint16_t> samples; // row 0 = top
};

// Reads the PNG's pixels (OpenImageIO) and its tEXt chunks (read here, byte by byte).
Png readPng(const std::string& path);

// A DEM of `w` x `w` samples from f(x, y) (x east, y north, in samples), encoded as NAME.dat in
// `dir` (tiles of 32 intervals, the scale chosen by the encoder); returns its path.
std::string demOf(const TempDir& dir, const std::string& name, int w, double (*f)(double, double));

} // namespace pyramid::test
