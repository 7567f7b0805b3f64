// The residual tiles every writer makes, decoded without libtiff: a TIFF of one directory, in
// strips, uncompressed or Deflate, with or without the horizontal predictor, holding 2 x 8-bit
// (the original tools' layout) or 1 x 16-bit samples (doc/format.md 1.7). Opening a TIFF with
// libtiff sets up its whole field table for every tile, which costs about as much as the
// tile's Deflate stream; the runtime decodes a residual tile per elevation tile.
//
// libtiff stays the reference: anything this reader does not recognise exactly (other tags,
// codecs, layouts, any inconsistency) makes it decline, and the caller decodes the blob with
// libtiff, which gives its own result or error (formats/residual_codec.cpp).
#pragma once
#include <cstdint>
#include <span>

namespace pyramid {

// Decodes `blob`, a residual tile of size x size samples, into `out` (size * size samples, rows
// as stored) and returns true; or returns false, with `out` in any state, when the blob is not
// such a TIFF or cannot be decoded exactly.
bool decodePlainResidualTiff(std::span<const uint8_t> blob, int size, std::span<int16_t> out);

} // namespace pyramid
