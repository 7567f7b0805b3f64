// `pyramid verify FILE --gl`: every tile of a pyramid file produced on the CPU and on the GPU
// (headless EGL) and compared.
//
// * Residual files: for every elevation tile size n = tileSize / 2^k (k = 0..minLevel, with
//   delta = minLevel - k), every tile of every level: zf, zc and zm of ElevationProducer and
//   GlElevationProducer. Any differing bit is a difference; its size is counted in ULPs.
// * Ortho files with DXT tiles: the compressed bytes read back from the GPU must equal the
//   file's; the GPU's decoding is compared with the CPU decoder (libsquish) within
//   kDxtDecodeTolerance, since S3TC decoders legitimately round interpolated colours differently.
// * Ortho TIFF files: the tiles sampled back from their textures must equal the decoded tiles;
//   with 2-pixel borders the file is also rebuilt as colour residuals (the GPU upsample against
//   the CPU arithmetic), which must agree bit for bit whatever the file holds.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pyramid {

// Largest per-channel difference accepted between a GPU's S3TC decoding and libsquish's.
inline constexpr double kDxtDecodeTolerance = 3.0;

struct GlVerifyOptions {
    int maxLevel = -1; // deepest level compared (-1: every level)
};

struct GlVerifyPart {
    std::string what;           // "elevation n=192 delta=3", "colour residuals", ...
    std::string unit;           // "ulp" (floats) or "abs" (bytes)
    int64_t tiles = 0;          // tiles compared
    int64_t differingTiles = 0; // tiles with any difference
    double maxDifference = 0.0;
    double tolerance = 0.0;     // 0: bit for bit
    bool ok() const { return maxDifference <= tolerance; }
};

struct GlVerifyReport {
    std::string file;
    std::string renderer; // GL_RENDERER of the context used
    std::vector<GlVerifyPart> parts;
    bool ok() const;
};

// Throws GlUnavailable when no EGL device exists, Error on unreadable files.
GlVerifyReport verifyOnGl(const std::string& path, const GlVerifyOptions& options = {});

nlohmann::json toJson(const GlVerifyReport& report);

// Distance between two floats in units in the last place: 0 iff the bits are equal (so +0 and
// -0 are 1 apart); NaNs are as far as their bit patterns.
uint64_t ulpDistance(float a, float b);

} // namespace pyramid
