// DXT1 / DXT5 block streams (no container), as ortho files store them: encoded by stb_dxt
// (fast) or libsquish (slow, a little closer), decoded by libsquish.
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
//   0 = stb_dxt, one refinement step (fastest)
//   1 = stb_dxt, two refinement steps
//   2 = libsquish's cluster fit
//   3 = libsquish's iterative cluster fit (best, slowest)
std::vector<uint8_t> encodeDxt(std::span<const uint8_t> pixels, int width, int height, int channels,
                               DxtFormat format, int quality = 1);

constexpr int kDxtQualityLevels = 4;

// Decodes to width x height x outChannels (3 for DXT1, 4 for DXT5) bytes.
// Throws Error("WHERE: ...") if the blob does not have exactly dxtBytes() bytes.
std::vector<uint8_t> decodeDxt(std::span<const uint8_t> blob, int width, int height, DxtFormat format,
                               const std::string& where);

} // namespace pyramid
