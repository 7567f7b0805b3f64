// The residual tiles every writer makes, decoded and written without libtiff: a TIFF of one
// directory, in strips, uncompressed or Deflate, with or without the horizontal predictor,
// holding 2 x 8-bit (the original tools' layout) or 1 x 16-bit samples (doc/format.md 1.7).
// Opening a TIFF with libtiff sets up its whole field table for every tile: about 20 us, as
// much as the tile's Deflate stream when the runtime decodes it, and 3 % of the DEM encoder's
// time when it writes one.
//
// libtiff stays the reference: anything this reader does not recognise exactly (other tags,
// codecs, layouts, any inconsistency) makes it decline, and the caller decodes the blob with
// libtiff, which gives its own result or error (formats/residual_codec.cpp); the writer makes
// the bytes libtiff makes of the same tile (tests/formats_tiles_test.cpp holds it to them).
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
// writePlainResidualTiff: the same bytes on every machine. Sizes 1 to 65535.
std::vector<uint8_t> encodeResidualTiff(std::span<const int16_t> residuals, int size, int deflateLevel = 6,
                                        ResidualTiffLayout layout = ResidualTiffLayout::TwoBytes,
                                        bool horizontalPredictor = false);
// The TIFF of one residual tile of size x size samples (size < 65536) in one Deflate strip,
// `deflated` (the strip's zlib stream), byte for byte as libtiff 4 writes it on a
// little-endian machine: "II", the strip at byte 8, then the directory at the next even
// offset, its tags in order. 2 x 8-bit samples, or 1 x 16-bit signed ones with `oneShort`;
// Predictor = 2 with `predictor`; Orientation = 4 (bottom-left), as every residual tile.
std::vector<uint8_t> writePlainResidualTiff(std::span<const uint8_t> deflated, int size, bool oneShort, bool predictor);

// Decodes `blob`, a residual tile of size x size samples, into `out` (size * size samples, rows
// as stored) and returns true; or returns false, with `out` in any state, when the blob is not
// such a TIFF or cannot be decoded exactly.
bool decodePlainResidualTiff(std::span<const uint8_t> blob, int size, std::span<int16_t> out);

} // namespace pyramid
