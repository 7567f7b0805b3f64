// PNG images encoded in memory, for answers over HTTP (preview/'s PngWriter writes files).
#pragma once
#include <cstdint>
#include <string>

namespace pyramid::serve {

// An 8-bit PNG of `width` x `height` pixels of `channels` (1 grey, 2 grey and alpha, 3 RGB,
// 4 RGBA) from `pixels` (rows of width x channels bytes), the first row of `pixels` as the
// image's top row. Compressed for speed (zlib level 1, no filter): the tiles are small and
// served often. Throws Error on a failure of libpng.
std::string encodePng(const uint8_t* pixels, int width, int height, int channels);

} // namespace pyramid::serve
