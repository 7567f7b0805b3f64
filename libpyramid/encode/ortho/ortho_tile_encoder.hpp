// One ortho tile encoded for each output of encodeOrtho (ortho_encoder.hpp): its TIFF tile,
// its DXT tile and its colour residual tile (closed loop), with the statistics of their errors.
// Thread-safe: the tiles of a group are encoded in parallel.
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <tuple>
#include <vector>

#include "formats/ortho_file.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"

namespace pyramid {

// What a tile adds to its level's statistics (OrthoLevelReport).
struct OrthoTileStats {
    int64_t tiles = 1; // 0 for the statistics of a tile's later outputs (a second walk's)
    int tiffMaxError = 0;
    int64_t jpegTiles = 0;
    double dxtSquares = 0.0;
    int64_t dxtSamples = 0;
    int residualMaxError = 0;
    double residualSquares = 0.0;
    int64_t residualSamples = 0;
    int64_t clamped = 0;
};

// Bytes that never change once made: a uniform tile's are shared by every tile of its colour
// (OrthoTileEncoder::encode), so that the hundreds of thousands of blank tiles of a face a small
// map barely touches cost a pointer each, not a copy.
using SharedBytes = std::shared_ptr<const std::vector<uint8_t>>;

// `bytes`, or no bytes when null.
inline const std::vector<uint8_t>& bytesOf(const SharedBytes& bytes) {
    static const std::vector<uint8_t> none;
    return bytes ? *bytes : none;
}

// A tile's bytes in each output (null for an output not written).
struct EncodedOrthoTile {
    int level = 0, tx = 0, ty = 0;
    SharedBytes tiff, dxt, residual;
    SharedBytes recon; // colour-residual reconstruction, for the children
    OrthoTileStats stats;
    // The bytes are a uniform tile's, shared by every tile of its colour, and stay alive as long
    // as the encoder: a writer may store them once and give the other tiles the same range.
    bool uniform = false;
    // A pruned walk's (OrthoLevels::walk): the TIFF and DXT outputs hold an empty subtree here
    // (this tile and every one below it blank; no TIFF or DXT bytes), and the colour residual
    // output one of residual 128 (no residual bytes).
    bool picturesEmptyBelow = false;
    bool residualEmptyBelow = false;
    bool top = false;    // from an item of levels 0..C
    int64_t covers = 1;  // the tiles of the pyramid this entry stands for (progress)
};

class OrthoTileEncoder {
public:
    OrthoTileEncoder(const OrthoLevels& levels, const OrthoEncodeOptions& o) : o_(o) {
        channels_ = levels.channels();
        tileSize_ = levels.tileSize();
    }

    // `parentRecon`: the parent's colour-residual reconstruction (residuals written, level > 0),
    // else nullptr.
    EncodedOrthoTile encode(const TrueTile& t, const std::vector<uint8_t>* parentRecon) const;

private:
    // A uniform tile's colour (its 1 to 4 channels packed) and TIFF compression (which may
    // depend on the tile's place).
    using UniformKey = std::tuple<uint32_t, TiffCompression>;

    // The key of a tile of level > 0 whose pixels are all of one colour, else nothing.
    std::optional<UniformKey> uniformKey(const TrueTile& t) const;
    static EncodedOrthoTile placed(const EncodedOrthoTile& shared, const TrueTile& t);
    TiffCompression tiffCompressionOf(const TrueTile& t) const;
    EncodedOrthoTile encodeNew(const TrueTile& t, const std::vector<uint8_t>* parentRecon) const;
    void encodeResidual(const TrueTile& t, const std::vector<uint8_t>* parent, EncodedOrthoTile& e) const;

    // The uniform tiles kept for reuse (kUniformTilesKept at most): kept_[0 .. keptCount_) are
    // published and never change, so that a lookup takes no lock (an empty face's millions of
    // tiles are lookups); new ones are added under keepMutex_.
    struct Kept {
        UniformKey key;
        EncodedOrthoTile tile;
    };
    static constexpr size_t kUniformTilesKept = 64;
    const Kept* findKept(const UniformKey& key) const;
    bool keptRecon(const std::vector<uint8_t>* recon) const;

    const OrthoEncodeOptions& o_;
    int channels_ = 0, tileSize_ = 0;
    mutable std::mutex keepMutex_;
    mutable std::array<Kept, kUniformTilesKept> kept_;
    mutable std::atomic<size_t> keptCount_{0};
};

} // namespace pyramid
