// libpyramid's DXT colour-block encoder (the default of --dxt-quality 0 and 1; doc/ortho-encoding.md,
// "DXT"): up to sixteen 4 x 4 blocks a call, one per vector lane, so that the per-block work (the
// principal axis, the endpoint fits) runs side by side instead of one dependency chain per
// block; 4, 8 or 16 lanes at a time, the widest vectors one register of the machine holds
// (SSE2, AVX2, AVX-512). For each block:
//
//  1. Candidates. (a) The block's principal axis (power iteration on the covariance of its 16
//     colours, from the covariance's largest column), and the extreme projections of its colours
//     on it, quantised to 5:6:5 as endpoints. (b) Its mean colour, rounded, coded by the pair of
//     5:6:5 endpoints per channel whose two-thirds colour comes closest (a table built once):
//     the whole answer for a block of one colour, and a good one for blocks whose spread is
//     below 5:6:5's steps.
//  2. Each candidate is evaluated as a decoder decodes it (dxt_codec.hpp's decodeDxtBlock: the
//     endpoints widened by bit replication, the thirds by truncating division): the endpoint
//     codes are ordered c0 > c1 (four colours), each pixel takes its nearest colour (squared
//     RGB distance, the lowest index on ties), and the block's squared error is summed. Equal
//     codes take index 0 everywhere (DXT1's third colour mode: index 3 would be transparent).
//  3. Refinement, `refinements` times: the endpoints that minimise the squared error for the
//     best candidate's indices (least squares, one 2 x 2 system shared by the channels),
//     quantised, are a new candidate; the block keeps whichever is best.
//
// Every lane runs the same IEEE single-precision operations in one written order (compiled
// without contraction), so the bytes do not depend on the vector width the CPU offers.
#pragma once
#include <cstdint>

namespace pyramid {

// The most blocks one call takes (the widest vectors' lanes).
constexpr int kDxtColourLanes = 16;

// Encodes `count` (1..kDxtColourLanes) blocks: blocks[i] is 16 RGBA pixels, row by row (alpha
// ignored), out[i] receives the 8-byte colour block. With `squaredErrors`, squaredErrors[i]
// receives block i's error as a DXT1 decoder decodes it (the sum over its 16 pixels of the
// squared R, G and B differences; exact, as every term is an integer and the sum stays below
// 2^24).
void encodeDxtColourBlocks(const uint8_t* const* blocks, uint8_t* const* out, int count, int refinements,
                           int* squaredErrors = nullptr);

// The lanes encodeDxtColourBlocks runs in on this machine: 16, 8 or 4.
int dxtColourLanes();
// Whether this machine runs the fit in vectors of `lanes` (4 always; 8 with AVX2, 16 with
// AVX-512, in x86-64 builds with vector clones: formats/vector_clones.hpp).
bool dxtColourLanesAvailable(int lanes);
// encodeDxtColourBlocks in vectors of `lanes`, which must be available: the same bytes and
// errors at every width (tests compare them).
void encodeDxtColourBlocksIn(int lanes, const uint8_t* const* blocks, uint8_t* const* out, int count,
                             int refinements, int* squaredErrors = nullptr);

} // namespace pyramid
