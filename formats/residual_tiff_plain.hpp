// The residual tiles every writer makes, decoded and written without libtiff: a TIFF of one
// directory, in strips, uncompressed or Deflate, with or without the horizontal predictor,
// holding 2 x 8-bit (the original tools' layout) or 1 x 16-bit samples (doc/format.md 1.7).
// Opening a TIFF with libtiff sets up its whole field table for every tile: about 20 us, as
// much as the tile's Deflate stream when the runtime decodes it.
//
// libtiff stays the reference: anything this reader does not recognise exactly (other tags,
// codecs, layouts, any inconsistency) makes it decline, and the caller decodes the blob with
// libtiff, which gives its own result or error (formats/residual_codec.cpp).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace pyramid {

// The layouts of residual TIFF tiles that every reader (the original runtime's too) decodes to
// the same bytes: TwoBytes is 2 samples x 8 bits (low byte, high byte), as the original tools
// write them; OneShort is 1 signed 16-bit sample.
enum class ResidualTiffLayout { TwoBytes, OneShort };

// Residual tiles: size x size int16 values, Deflate, by default as the original tools write
// them. `deflateLevel` (1..12, libdeflate's levels) only trades encoding time for bytes: any
// level is the same standard Deflate stream to a reader. `horizontalPredictor` stores each
// sample as its difference from the one to its left (TIFF Predictor = 2, per 8-bit channel or
// per 16-bit sample), which libtiff undoes within TIFFReadEncodedStrip. One strip, written by
// writePlainTiff (formats/tiff_plain_writer.hpp): the same bytes on every machine. Sizes 1 to
// 65535.
std::vector<uint8_t> encodeResidualTiff(std::span<const int16_t> residuals, int size, int deflateLevel = 6,
                                        ResidualTiffLayout layout = ResidualTiffLayout::TwoBytes,
                                        bool horizontalPredictor = false);

// What decodePlainResidualTiff made of a blob.
enum class PlainDecode {
    Decoded,  // `out` holds the tile
    Declined, // not such a TIFF, or not decoded exactly: libtiff decides (`out` in any state)
    Damaged,  // such a TIFF whose Deflate stream is corrupt or fails its Adler-32 check, which
              // libtiff does not verify (it stops reading once the strip is full)
};

// Decodes `blob`, a residual tile of size x size samples, into `out` (size * size samples, rows
// as stored).
PlainDecode decodePlainResidualTiff(std::span<const uint8_t> blob, int size, std::span<int16_t> out);

} // namespace pyramid
