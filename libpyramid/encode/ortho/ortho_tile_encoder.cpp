#include "libpyramid/encode/ortho/ortho_tile_encoder.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <span>

#include "formats/dxt_codec.hpp"
#include "formats/tiff_tile.hpp"
#include "libpyramid/filters/colour_upsample.hpp"

namespace pyramid {

namespace {

TiffCompression tiffCompression(TilePolicy p, bool edge, int channels) {
    switch (p) {
    case TilePolicy::Deflate:
        return TiffCompression::Deflate;
    case TilePolicy::Lzw:
        return TiffCompression::Lzw;
    case TilePolicy::Jpeg:
        return TiffCompression::Jpeg;
    case TilePolicy::JpegYCbCr:
        return TiffCompression::JpegYCbCr;
    case TilePolicy::None:
        return TiffCompression::None;
    case TilePolicy::Original:
        // JPEG inside, Deflate on the pyramid's outer edge; JPEG cannot hold 2 or 4 channels.
        return edge || channels == 2 || channels == 4 ? TiffCompression::Deflate : TiffCompression::Jpeg;
    }
    return TiffCompression::Deflate;
}

// The tile without its border when the output has none (empty with the border: the tile's own
// pixels are used, not a copy).
std::vector<uint8_t> crop(const Image8& tile, int border) {
    if (border == 2) {
        return {};
    }
    const int side = tile.width - 4;
    std::vector<uint8_t> out(static_cast<size_t>(side) * side * tile.channels);
    const size_t row = static_cast<size_t>(side) * tile.channels;
    for (int y = 0; y < side; ++y) {
        std::copy_n(tile.at(2, y + 2), row, &out[static_cast<size_t>(y) * row]);
    }
    return out;
}

// The Deflate level of a colour residual tile under the default (`residualDeflateLevel` 0,
// doc/ortho-encoding.md, "Compression policy of TIFF tiles"). Residuals that are smooth (their
// mean distance from 128 below 1/2: most are 128) compress fastest and smallest at level 2;
// grainy residuals take about half again as long at level 2 as at level 1, for 5 to 8 % fewer
// bytes, and get level 1. The root tile stores colours, not residuals: level 2. `distance` is
// the sum of the `samples` stored values' distances from 128, summed as they are computed
// (colour_upsample.hpp, RebuiltRow); JPEG residuals take no Deflate level.
int autoResidualDeflateLevel(uint64_t distance, size_t samples, int level) {
    if (level == 0) {
        return 2;
    }
    return 2 * distance < samples ? 2 : 1;
}

// The largest absolute difference between two runs of samples and the sum of its squares.
// Integers summed exactly (a tile's squares stay far below 2^53): the same total as adding
// them one by one in double precision. In chunks of 16 samples, which GCC vectorises at -O2
// too (it leaves loops that need a scalar remainder scalar there).
struct ErrorTotals {
    int maxError = 0;
    int64_t squares = 0;
};

ErrorTotals errorTotals(const uint8_t* __restrict a, const uint8_t* __restrict b, size_t count) {
    constexpr size_t kChunk = 16;
    ErrorTotals totals;
    const auto add = [&](size_t from, size_t to) {
        int chunkMax = 0, chunkSquares = 0; // at most 16 x 255^2: an int holds it
        for (size_t k = from; k < to; ++k) {
            const int err = std::abs(static_cast<int>(a[k]) - static_cast<int>(b[k]));
            chunkMax = std::max(chunkMax, err);
            chunkSquares += err * err;
        }
        totals.maxError = std::max(totals.maxError, chunkMax);
        totals.squares += chunkSquares;
    };
    size_t k = 0;
    for (; k + kChunk <= count; k += kChunk) {
        add(k, k + kChunk);
    }
    for (; k < count; k += kChunk) {
        add(k, std::min(count, k + kChunk));
    }
    return totals;
}

// Every pixel of `v` is its first one: every byte equals the one a pixel earlier (one memcmp,
// which stops at the first difference).
bool uniformPixels(std::span<const uint8_t> v, size_t channels) {
    return v.size() >= channels && std::memcmp(v.data(), v.data() + channels, v.size() - channels) == 0;
}

} // namespace

EncodedOrthoTile OrthoTileEncoder::encode(const TrueTile& t, const std::vector<uint8_t>* parentRecon) const {
    // Tiles of one colour under a parent of that colour (the black beyond a non-square
    // input, sea, snow) encode to the same bytes wherever they are: encoded once per colour
    // and compression, then copied. At most kUniformTilesKept colours are kept (memory
    // stays bounded on a map of many flat colours; later ones are encoded as any tile).
    // The copies share the bytes (SharedBytes).
    const std::optional<UniformKey> key = uniformKey(t);
    if (!key) {
        return encodeNew(t, parentRecon);
    }
    const auto c = static_cast<size_t>(channels_);
    // With residuals, the parent's rebuilt colours must be the tile's colour too: known without
    // looking for a kept tile's, else looked at.
    if (o_.writeResiduals) {
        if (parentRecon == nullptr ||
            !((keptRecon(parentRecon) || uniformPixels(*parentRecon, c)) &&
              std::memcmp(parentRecon->data(), t.image().pixels.data(), c) == 0)) {
            return encodeNew(t, parentRecon);
        }
    }
    if (const Kept* shared = findKept(*key)) {
        return placed(shared->tile, t);
    }
    EncodedOrthoTile e = encodeNew(t, parentRecon);
    e.uniform = true;
    const std::lock_guard<std::mutex> lock(keepMutex_);
    const size_t n = keptCount_.load(std::memory_order_relaxed);
    if (n < kUniformTilesKept && findKept(*key) == nullptr) {
        kept_[n] = Kept{*key, e};
        keptCount_.store(n + 1, std::memory_order_release); // published whole
    } else {
        e.uniform = false; // not kept: its bytes are its own
    }
    return e;
}

const OrthoTileEncoder::Kept* OrthoTileEncoder::findKept(const UniformKey& key) const {
    const size_t n = keptCount_.load(std::memory_order_acquire);
    for (size_t k = 0; k < n; ++k) {
        if (kept_[k].key == key) {
            return &kept_[k];
        }
    }
    return nullptr;
}

bool OrthoTileEncoder::keptRecon(const std::vector<uint8_t>* recon) const {
    const size_t n = keptCount_.load(std::memory_order_acquire);
    for (size_t k = 0; k < n; ++k) {
        if (kept_[k].tile.recon.get() == recon) {
            return true;
        }
    }
    return false;
}

std::optional<OrthoTileEncoder::UniformKey> OrthoTileEncoder::uniformKey(const TrueTile& t) const {
    if (t.level == 0) {
        return std::nullopt; // the root's residual tile holds the colours themselves
    }
    const PixelBytes& p = t.image().pixels;
    const auto c = static_cast<size_t>(channels_);
    if (!(t.blank || uniformPixels(p, c))) {
        return std::nullopt;
    }
    uint32_t colour = 0;
    for (size_t k = 0; k < c; ++k) {
        colour |= static_cast<uint32_t>(p[k]) << (8 * k);
    }
    return UniformKey{colour, tiffCompressionOf(t)};
}

EncodedOrthoTile OrthoTileEncoder::placed(const EncodedOrthoTile& shared, const TrueTile& t) {
    EncodedOrthoTile e = shared;
    e.level = t.level;
    e.tx = t.tx;
    e.ty = t.ty;
    return e;
}

TiffCompression OrthoTileEncoder::tiffCompressionOf(const TrueTile& t) const {
    const int last = (1 << t.level) - 1;
    const bool edge = t.tx == 0 || t.ty == 0 || t.tx == last || t.ty == last;
    return tiffCompression(o_.compression, edge, channels_);
}

EncodedOrthoTile OrthoTileEncoder::encodeNew(const TrueTile& t, const std::vector<uint8_t>* parentRecon) const {
    EncodedOrthoTile e;
    e.level = t.level;
    e.tx = t.tx;
    e.ty = t.ty;
    const int outSide = tileSize_ + 2 * o_.border;
    const Image8& image = t.image();
    const std::vector<uint8_t> cropped = crop(image, o_.border);
    const std::span<const uint8_t> plain = o_.border == 2 ? std::span<const uint8_t>(image.pixels)
                                                          : std::span<const uint8_t>(cropped);
    if (o_.writeTiff) {
        const TiffCompression c = tiffCompressionOf(t);
        // Deflate with the horizontal predictor, which readers undo inside libtiff.
        std::vector<uint8_t> tiff = encodeTiff8(plain, outSide, outSide, channels_, c, o_.jpegQuality, o_.deflateLevel, true);
        e.stats.jpegTiles += isJpeg(c);
        if (isJpeg(c) && o_.measureJpegError) {
            const std::vector<uint8_t> back = decodeOrthoTiff(tiff, outSide, channels_, "JPEG tile");
            // A local maximum (not the member, which the byte loads might alias) vectorises.
            int maxError = 0;
            for (size_t k = 0; k < back.size(); ++k) {
                const int d = static_cast<int>(back[k]) - static_cast<int>(plain[k]);
                maxError = std::max(maxError, d < 0 ? -d : d);
            }
            e.stats.tiffMaxError = maxError;
        }
        e.tiff = std::make_shared<const std::vector<uint8_t>>(std::move(tiff));
    }
    if (o_.writeDxt) {
        const DxtFormat format = channels_ == 4 ? DxtFormat::Dxt5 : DxtFormat::Dxt1;
        // The error of the blocks as a reader decodes them (grey expanded to RGB), measured
        // block by block as they are encoded. An integer sum: the same total as adding the
        // squares one by one in double precision (a tile's stay far below 2^53).
        int64_t squares = 0;
        e.dxt = std::make_shared<const std::vector<uint8_t>>(
            encodeDxt(plain, outSide, outSide, channels_, format, o_.dxtQuality, &squares));
        e.stats.dxtSquares += static_cast<double>(squares);
        e.stats.dxtSamples += static_cast<int64_t>(outSide) * outSide * (format == DxtFormat::Dxt5 ? 4 : 3);
    }
    if (o_.writeResiduals) {
        encodeResidual(t, parentRecon, e);
    }
    return e;
}

// Closed loop: the stored residuals are decoded exactly as a reader will decode them, and
// the tile is rebuilt from them, before its children are predicted from it.
//
// The work is done row by row while the row is in cache: the prediction is written where the
// rebuilt row goes (e.recon), the residuals into a buffer kept per thread; with Deflate, whose
// residuals decode to themselves, the row is rebuilt and its error measured in the same pass
// (JPEG residuals are rebuilt from their decoded values once the tile is compressed).
void OrthoTileEncoder::encodeResidual(const TrueTile& t, const std::vector<uint8_t>* parent, EncodedOrthoTile& e) const {
    const int side = tileSize_ + 4;
    const PixelBytes& truth = t.image().pixels;
    const size_t count = truth.size();
    const size_t rowBytes = static_cast<size_t>(side) * static_cast<size_t>(channels_);
    const bool jpeg = o_.residualCompression == TilePolicy::Jpeg;
    thread_local std::vector<uint8_t> storedBuffer;
    storedBuffer.resize(count);
    uint8_t* const stored = storedBuffer.data();
    std::vector<uint8_t> reconBuffer(count);
    uint8_t* const recon = reconBuffer.data();
    int maxError = 0;
    int64_t squares = 0, clampedCount = 0;
    uint64_t spread = 0; // of the stored values from 128, while they are computed (Deflate)
    const auto measure = [&](const uint8_t* rebuilt, const uint8_t* original, size_t n) {
        const ErrorTotals row = errorTotals(rebuilt, original, n);
        maxError = std::max(maxError, row.maxError);
        squares += row.squares;
    };
    if (t.level > 0) { // the root stores its colours
        const int rx = (t.tx & 1) * (tileSize_ / 2);
        const int ry = (t.ty & 1) * (tileSize_ / 2);
        for (int y = 0; y < side; ++y) {
            const size_t offset = static_cast<size_t>(y) * rowBytes;
            const uint8_t* trueRow = truth.data() + offset;
            uint8_t* storedRow = stored + offset;
            uint8_t* row = recon + offset;
            predictColourRow(parent->data(), rowBytes, channels_, rx, ry, y, side, row);
            if (jpeg) {
                clampedCount += encodeColourResiduals(trueRow, row, rowBytes, storedRow);
            } else {
                // Nothing clamps, and every error is 0 or 1 (colour_upsample.hpp).
                const RebuiltRow r = encodeColourResidualsRebuilt(trueRow, row, rowBytes, storedRow);
                maxError = std::max(maxError, r.errors > 0 ? 1 : 0);
                squares += r.errors;
                spread += static_cast<uint64_t>(r.spread);
            }
        }
        e.stats.clamped += clampedCount;
    }
    const std::span<const uint8_t> storedTile(t.level == 0 ? truth.data() : stored, count);
    const int deflateLevel = o_.residualDeflateLevel != 0 ? o_.residualDeflateLevel
                                                          : autoResidualDeflateLevel(spread, count, t.level);
    std::vector<uint8_t> residual = encodeTiff8(storedTile, side, side, channels_,
                                                jpeg ? TiffCompression::Jpeg : TiffCompression::Deflate, o_.jpegQuality,
                                                deflateLevel);
    if (jpeg) {
        const std::vector<uint8_t> decoded = decodeOrthoTiff(residual, side, channels_, "JPEG residual tile");
        if (t.level == 0) {
            std::copy_n(decoded.data(), count, recon);
        } else {
            applyColourResiduals(recon, decoded.data(), count);
        }
        measure(recon, truth.data(), count);
    } else if (t.level == 0) {
        std::copy_n(truth.data(), count, recon); // Deflate is lossless: the colours themselves
    }
    e.stats.residualMaxError = std::max(e.stats.residualMaxError, maxError);
    e.stats.residualSquares += static_cast<double>(squares);
    e.stats.residualSamples += static_cast<int64_t>(count);
    e.residual = std::make_shared<const std::vector<uint8_t>>(std::move(residual));
    e.recon = std::make_shared<const std::vector<uint8_t>>(std::move(reconBuffer));
}

} // namespace pyramid
