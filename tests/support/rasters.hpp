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

// w x w heights, 0 except tall spikes at odd samples near the north-east corner (the last
// subtree in Z order, the finest grid's y running north): with 32-sample tiles over 8-sample
// roots, the automatic scale's first guess (from the in-memory grid of every 4th sample, which
// the spikes miss) overflows in the last subtrees only.
std::vector<float> overflowSpikes(int w);

// Three 8-bit channels with a pixel-sized texture (tiles differ and compress poorly), row 0 =
// north: imagery for ortho tests.
std::vector<uint16_t> texturedColours(int width, int height);

// Writes 8-bit (or 16-bit when `sixteen`) images with `channels` channels; row 0 = north.
void writeImage(const std::string& path, int width, int height, int channels, const std::vector<uint16_t>& values,
                bool sixteen);

} // namespace pyramid::test
