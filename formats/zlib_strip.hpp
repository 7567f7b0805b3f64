// A TIFF strip's zlib stream (Deflate, compression 8 or 32946) inflated whole, its Adler-32
// checked. libtiff inflates a strip only until the strip is full: it never reads the checksum of
// a stream that runs long, so damage that makes a stream run long (most garbage does) would pass
// unseen, giving wrong pixels or residuals without an error. Every tile reader of the formats
// inflates its Deflate strips here (residual_tiff_plain.cpp, tiff_tile.cpp), and the TIFF tile
// reader undoes libtiff's predictor after.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

namespace pyramid {

enum class StripInflate {
    Inflated,    // `out` holds the strip's bytes, the stream whole and its checksum right
    Damaged,     // the stream is corrupt, or fails its checksum (whether it runs long or not)
    OtherLength, // a whole stream of other than out.size() bytes (`out` in any state): a TIFF
                 // reader decides (libtiff reads a longer one's first bytes, refuses a shorter one)
};

StripInflate inflateStrip(std::span<const uint8_t> stream, std::span<uint8_t> out);

// What libtiff does to a strip's inflated bytes (rows of `rowBytes`, samples of 8 or 16 bits,
// `channels` a pixel): 16-bit samples of a file in the other byte order (`swapped`) to this
// machine's, then, with the horizontal predictor, each sample plus the same channel of the pixel
// to its left, modulo 2^bits, along each row.
void undoTiffPredictor(std::span<uint8_t> strip, size_t rowBytes, int channels, int bits, bool swapped,
                       bool horizontal);

} // namespace pyramid
