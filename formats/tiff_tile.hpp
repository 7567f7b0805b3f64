// One-strip TIFF tiles encoded and decoded in memory through libtiff (no temporary files).
// Pixel rows are in strip order: row 0 of the array is the first row of the strip, which
// pyramid files use for the tile's bottom row (the tiles carry Orientation = bottom-left).
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pyramid {

// Jpeg: RGB (or grey) components, no chroma subsampling, as the original runtime reads them.
// JpegYCbCr: RGB tiles stored as YCbCr with 2 x 2 chroma subsampling (grey tiles as Jpeg):
// about a third of the bytes; libtiff readers must ask for RGB (JPEGCOLORMODE), which the
// original runtime does not.
enum class TiffCompression { None, Deflate, Lzw, Jpeg, JpegYCbCr };

inline bool isJpeg(TiffCompression c) { return c == TiffCompression::Jpeg || c == TiffCompression::JpegYCbCr; }

struct TiffImage {
    int width = 0;
    int height = 0;
    int channels = 0;
    int bitsPerSample = 0; // 8 or 16
    bool signedSamples = false;
    std::vector<uint8_t> pixels; // width * height * channels * bitsPerSample/8, native endian
};

// Encodes 8-bit pixels (channels 1..4; 3 and 4 as RGB, 1 and 2 as min-is-black).
// `deflateLevel` (1..12, libdeflate's levels) and `horizontalPredictor` (TIFF Predictor = 2:
// each sample stored as its difference from the same channel of the pixel to its left) apply to
// Deflate only, `jpegQuality` (1..100) to JPEG; a level or quality out of range is an error. Both
// are undone by any libtiff reader within TIFFReadEncodedStrip, so the decoded pixels are the
// same whatever they are. At Deflate levels 1 and 2, strips of noise (a 16 KB sample takes at
// least 3 bits a byte in a literal code, and no fewer in libdeflate level 1's stream) are coded
// as one block of literals, an ordinary Deflate stream (formats/deflate_literals.hpp).
std::vector<uint8_t> encodeTiff8(std::span<const uint8_t> pixels, int width, int height, int channels,
                                 TiffCompression compression, int jpegQuality = 90, int deflateLevel = 6,
                                 bool horizontalPredictor = false);

// Decodes any one-strip (or multi-strip) contiguous TIFF of 8 or 16 bits per sample,
// rejecting images larger than maxWidth x maxHeight before allocating anything.
// `where` prefixes error messages (e.g. "DEM.dat: tile (3,1,0)").
TiffImage decodeTiff(std::span<const uint8_t> blob, int maxWidth, int maxHeight, const std::string& where);

// A residual tile read by libtiff, the reference (formats/residual_tiff_plain.hpp writes them and
// reads the usual ones without it): accepts the 2 x 8-bit layout and a genuine 1 x 16-bit
// layout; the image must be size x size.
std::vector<int16_t> decodeResidualTiff(std::span<const uint8_t> blob, int size, const std::string& where);

// Ortho tiles: exactly size x size x channels 8-bit samples (4-channel tiles without an
// ExtraSamples tag are accepted, as the original tools write them).
std::vector<uint8_t> decodeOrthoTiff(std::span<const uint8_t> blob, int size, int channels,
                                     const std::string& where);

// The quantisation tables of a JPEG TIFF tile: for each component of its frame (the strip's
// SOF), the 64 divisors of the table it uses (in the stream's zig-zag order), from the strip's
// own stream or the JPEGTables tag; `ycbcr` when the tile is stored as YCbCr (Photometric).
// nullopt for a tile of another compression. Throws Error (prefixed by `where`) for a damaged
// stream or a component without its table.
struct JpegTileTables {
    bool ycbcr = false;
    std::vector<std::array<uint16_t, 64>> components;
};
std::optional<JpegTileTables> jpegTileTables(std::span<const uint8_t> blob, const std::string& where);

// The compression of a TIFF blob, for reports: "deflate", "deflate-legacy" (code 32946),
// "lzw", "jpeg", "none", "packbits", "compression-N", or "invalid".
std::string describeTiff(std::span<const uint8_t> blob);

} // namespace pyramid
