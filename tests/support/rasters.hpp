// Small rasters for tests, written with OpenImageIO.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pyramid::test {

// Writes a one-channel float32 TIFF of width x height; row 0 = north.
void writeFloatRaster(const std::string& path, int width, int height, const std::vector<float>& values);

// A deterministic terrain-like height field: smooth hills, a slope and small-scale noise,
// non-integer values (metres), row 0 = north.
std::vector<float> syntheticHeights(int width, int height, float amplitude = 1000.0f);

// Three 8-bit channels with a pixel-sized texture (tiles differ and compress poorly), row 0 =
// north: imagery for ortho tests.
std::vector<uint16_t> texturedColours(int width, int height);

// Writes 8-bit (or 16-bit when `sixteen`) images with `channels` channels; row 0 = north.
void writeImage(const std::string& path, int width, int height, int channels, const std::vector<uint16_t>& values,
                bool sixteen);

} // namespace pyramid::test
