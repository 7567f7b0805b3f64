// DXT1 / DXT5 block streams (no container), as ortho files store them: encoded by libpyramid's
// colour fit (dxt_colour_fit.hpp, fast) or libsquish (slow), decoded as libsquish decodes.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pyramid {

enum class DxtFormat { Dxt1, Dxt5 };

// Bytes of a width x height image: 8 (DXT1) or 16 (DXT5) per 4x4 block.
size_t dxtBytes(int width, int height, DxtFormat format);

// `pixels`: width x height x channels (1..4) bytes. 1-3 channels are expanded to RGB
// (grey replicated) and encoded as DXT1, 4 channels must use DXT5.
// quality (encoders and figures in doc/ortho-encoding.md, "DXT"):
//   0 = the colour fit, one refinement (fastest)
//   1 = the colour fit, up to two refinements
//   2 = libsquish's cluster fit
//   3 = libsquish's iterative cluster fit (best, slowest)
std::vector<uint8_t> encodeDxt(std::span<const uint8_t> pixels, int width, int height, int channels,
                               DxtFormat format, int quality = 1);

// encodeDxt, and the error of the blocks as decodeDxt decodes them: the sum over the image's
// pixels of the squared differences between the decoded samples (3 for DXT1, 4 for DXT5) and
// the pixels given (grey replicated into R, G and B). Each block is decoded right after it is
// encoded, while it is in cache, instead of decoding the whole tile again.
std::vector<uint8_t> encodeDxt(std::span<const uint8_t> pixels, int width, int height, int channels,
                               DxtFormat format, int quality, int64_t* squaredError);

constexpr int kDxtQualityLevels = 4;

// One 4 x 4 block (8 bytes for DXT1, 16 for DXT5) decoded to 16 RGBA pixels, row by row, as
// decodeDxt decodes it (DXT1: alpha 255, or 0 for the transparent colour of 3-colour blocks).
void decodeDxtBlock(const uint8_t* bytes, DxtFormat format, uint8_t* rgba);

// Decodes to width x height x outChannels (3 for DXT1, 4 for DXT5) bytes.
// Throws Error("WHERE: ...") if the blob does not have exactly dxtBytes() bytes.
std::vector<uint8_t> decodeDxt(std::span<const uint8_t> blob, int width, int height, DxtFormat format,
                               const std::string& where);

} // namespace pyramid
