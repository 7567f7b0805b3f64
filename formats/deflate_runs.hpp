// A zlib stream of literals and runs: one dynamic-Huffman Deflate block whose only matches
// repeat the byte before or the pixel before (distances 1 and `pixelBytes`). Natural imagery
// after the horizontal predictor is mostly literals, and most of what a general match finder
// finds in it are such runs (flat sky, sea, shadow); looking only there is about twice as fast
// as libdeflate level 1, whose stream of such bytes it comes within a few percent of, or beats
// (bench/ortho_bench.md, 2026-12-03). Texture that repeats farther away needs a real match finder:
// tiff_strip_bytes.cpp chooses per strip. Any inflater reads the stream (RFC 1950/1951).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pyramid {

// Writes the zlib stream of `bytes` (runs at distances 1 and `pixelBytes`, 1 to 4) into `out`
// (resized to fit) and returns its size.
size_t deflateRuns(std::span<const uint8_t> bytes, int pixelBytes, std::vector<uint8_t>& out);

} // namespace pyramid
