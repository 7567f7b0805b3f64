// How the tiles of a residual (DEM) file are coded (doc/format.md, 1.3 and 1.8): the one owner of
// the codecs' names, their Deflate levels and the rule that tells a stored blob's codec.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pyramid {

enum class ResidualCodec {
    Deflate,  // 2 x 8-bit TIFF tiles, Deflate, as the original tools write them (the default)
    Smallest, // per tile, the smallest TIFF the original runtime reads the same: 2 x 8 or 1 x 16
              // bits, with or without the horizontal predictor (three Deflate runs a tile)
    Context,  // context-coded tiles (formats/residual_context.hpp): the smallest files, read by
              // libpyramid's readers only, not by the original runtime
};

// "deflate", "smallest", "context".
const char* residualCodecName(ResidualCodec codec);
std::optional<ResidualCodec> parseResidualCodec(const std::string& name);

struct ResidualTileCoding {
    ResidualCodec codec = ResidualCodec::Deflate;
    // libdeflate's level, 1..12, for the TIFF codecs; 0: the codec's default, 2 for Deflate (fast)
    // and 12 for Smallest (an archival build). Context coding has no level.
    int deflateLevel = 0;

    // The level the TIFF codecs use.
    int effectiveDeflateLevel() const;
    // Throws OptionError("deflateLevel") for a level beyond 0..12, or any level with Context.
    void validate() const;
};

// Codes size x size residuals (rows as the file stores them) as `coding` says.
std::vector<uint8_t> encodeResidualBlob(std::span<const int16_t> residuals, int size, const ResidualTileCoding& coding);

// Decodes a stored residual tile of any codec: a TIFF (2 x 8 or 1 x 16 bits, any compression
// libtiff reads) or a context-coded blob, told apart by their first bytes. `parentPlane`: the
// tile's parent plane (formats/residual_shadow.hpp), which only a context-coded blob in the
// parent mode needs (contextBlobNeedsParent); ResidualFileReader supplies it.
std::vector<int16_t> decodeResidualBlob(std::span<const uint8_t> blob, int size, const std::string& where,
                                        std::span<const int32_t> parentPlane = {});
// The same into `out` (size * size samples), for readers that reuse their buffers.
void decodeResidualBlobInto(std::span<const uint8_t> blob, int size, const std::string& where, std::span<int16_t> out,
                            std::span<const int32_t> parentPlane = {});

// A stored tile's coding, for reports: "context" or describeTiff's name ("deflate", ...).
std::string describeResidualBlob(std::span<const uint8_t> blob);

} // namespace pyramid
