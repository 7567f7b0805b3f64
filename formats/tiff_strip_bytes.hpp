// The bytes of a Deflate strip as the TIFF tile writer stores them (formats/tiff_tile.cpp): the
// horizontal predictor's differences, and the strip's zlib stream, by libdeflate with one
// compressor per thread and level, or, for noise, as literals only (deflate_literals.hpp). Each
// result lives in a buffer of the calling thread's, valid until its next call of the same function.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

namespace pyramid {

// A zlib stream of `bytes` at libdeflate level `level` (1 to 12).
std::span<const uint8_t> zlibCompress(std::span<const uint8_t> bytes, int level);
// The zlib stream of a strip: with `pixelBytes` (8-bit image tiles of 1 to 4 channels; 0 for
// others) at levels 1 and 2, bytes on which Deflate's matches would save little are coded as
// literals only, or as literals and runs; the rest by libdeflate.
std::span<const uint8_t> deflateStrip(std::span<const uint8_t> bytes, int level, int pixelBytes);
// The strip libtiff's horizontal predictor stores for 8-bit samples.
std::span<const uint8_t> horizontalDifferences(const uint8_t* pixels, size_t bytes, int width, int channels);

} // namespace pyramid
