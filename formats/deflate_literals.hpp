// A zlib stream of literals only: one dynamic-Huffman Deflate block coding every byte as a
// literal (no matches), for bytes in which a match finder finds almost nothing (the sensor noise
// of imagery after the horizontal predictor, grainy colour residuals). Any inflater reads it
// (zlib, libtiff's Deflate codec, libdeflate): it is an ordinary RFC 1950/1951 stream. zlib's
// own literals-only strategy (Z_HUFFMAN_ONLY) writes the same kind of stream, but at about
// 150 MB/s on a tile of such noise, against about 115 MB/s for libdeflate level 1 and about
// 960 MB/s here (bench/ortho_bench.md, 2026-12-03): on noisy imagery the difference is most of
// the run's Deflate time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pyramid {

// Byte counts of `bytes` and what coding them as literals costs.
struct LiteralCost {
    uint32_t counts[256] = {};
    uint8_t lengths[257] = {}; // code lengths of the literals and the end of block (symbol 256)
    uint64_t bits = 0;         // the block's coded literals and end of block, without its header
};

// Counts the bytes and sizes their length-limited Huffman code.
LiteralCost literalCost(std::span<const uint8_t> bytes);

// Writes the zlib stream of `bytes` (header, one final dynamic block of literals and the
// end-of-block code, Adler-32) into `out` (resized to fit) and returns its size. `cost` is
// literalCost(bytes).
size_t deflateLiterals(std::span<const uint8_t> bytes, const LiteralCost& cost, std::vector<uint8_t>& out);

} // namespace pyramid
