#include "libpyramid/input/tiff_block_reader.hpp"

#include <libdeflate.h>
#include <tiffio.h>

#include <algorithm>
#include <bit>
#include <cstring>

#include "formats/error.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"

namespace pyramid {

std::unique_ptr<TiffBlockReader> TiffBlockReader::open(const std::string& path, const RasterInfo& info, int cacheMegabytes) {
    if (info.formatName != "tiff" || info.channels != 1) {
        return nullptr;
    }
    std::unique_ptr<TiffBlockReader> b(new TiffBlockReader());
    b->path_ = path;
    TIFF* tif = b->openHandle();
    if (!tif) {
        return nullptr;
    }
    uint32_t width = 0, height = 0;
    uint16_t compression = 0, channels = 0, photometric = 0;
    TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &width);
    TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &height);
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &compression);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &b->bits_);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &b->format_);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &channels);
    TIFFGetFieldDefaulted(tif, TIFFTAG_PHOTOMETRIC, &photometric);
    b->tiled_ = TIFFIsTiled(tif) != 0;
    if (b->tiled_) {
        TIFFGetField(tif, TIFFTAG_TILEWIDTH, &b->blockWidth_);
        TIFFGetField(tif, TIFFTAG_TILELENGTH, &b->blockHeight_);
    } else {
        b->blockWidth_ = width;
        TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &b->blockHeight_);
        b->blockHeight_ = std::min(b->blockHeight_, height);
    }
    b->width_ = width;
    b->height_ = height;
    const bool lossless = compression == COMPRESSION_NONE || compression == COMPRESSION_LZW ||
                          compression == COMPRESSION_ADOBE_DEFLATE || compression == COMPRESSION_DEFLATE ||
                          compression == COMPRESSION_PACKBITS || compression == COMPRESSION_ZSTD ||
                          compression == COMPRESSION_LZMA;
    const bool integer = (b->format_ == SAMPLEFORMAT_INT || b->format_ == SAMPLEFORMAT_UINT) &&
                         (b->bits_ == 8 || b->bits_ == 16 || b->bits_ == 32);
    const bool real = b->format_ == SAMPLEFORMAT_IEEEFP && b->bits_ == 32;
    const bool ok = lossless && (integer || real) && channels == 1 && photometric == PHOTOMETRIC_MINISBLACK &&
                    width == static_cast<uint32_t>(info.width) && height == static_cast<uint32_t>(info.height) &&
                    b->blockWidth_ > 0 && b->blockHeight_ > 0 && TIFFIsCODECConfigured(compression);
    if (!ok) {
        TIFFClose(tif);
        return nullptr;
    }
    uint16_t predictor = PREDICTOR_NONE;
    TIFFGetFieldDefaulted(tif, TIFFTAG_PREDICTOR, &predictor);
    b->floatPredictorDeflate_ = real && predictor == PREDICTOR_FLOATINGPOINT &&
                                (compression == COMPRESSION_ADOBE_DEFLATE || compression == COMPRESSION_DEFLATE);
    b->blocksAcross_ = (width + b->blockWidth_ - 1) / b->blockWidth_;
    b->budget_ = static_cast<size_t>(std::max(cacheMegabytes, 1)) << 20;
    b->idle_.push_back(tif);
    return b;
}

TiffBlockReader::~TiffBlockReader() {
    for (TIFF* tif : idle_) {
        TIFFClose(tif);
    }
}

void TiffBlockReader::read(int x0, int y0, int x1, int y1, float* out) {
    const size_t outWidth = static_cast<size_t>(x1 - x0);
    for (uint32_t by = static_cast<uint32_t>(y0) / blockHeight_; by * blockHeight_ < static_cast<uint32_t>(y1); ++by) {
        for (uint32_t bx = static_cast<uint32_t>(x0) / blockWidth_; bx * blockWidth_ < static_cast<uint32_t>(x1);
             ++bx) {
            const std::shared_ptr<const std::vector<float>> block = get(bx, by);
            const int bx0 = static_cast<int>(bx * blockWidth_), by0 = static_cast<int>(by * blockHeight_);
            const int cx0 = std::max(x0, bx0), cx1 = std::min(x1, bx0 + static_cast<int>(blockWidth_));
            const int cy0 = std::max(y0, by0), cy1 = std::min(y1, by0 + static_cast<int>(blockHeight_));
            for (int y = cy0; y < cy1; ++y) {
                const float* from = block->data() + static_cast<size_t>(y - by0) * blockWidth_ + (cx0 - bx0);
                std::copy(from, from + (cx1 - cx0), out + static_cast<size_t>(y - y0) * outWidth + (cx0 - x0));
            }
        }
    }
}

TIFF* TiffBlockReader::openHandle() const {
    return openTiffQuietly(path_, "r");
}

// Block (bx, by), decoded; from the cache or decoded now (outside the lock).
std::shared_ptr<const std::vector<float>> TiffBlockReader::get(uint32_t bx, uint32_t by) {
    const uint32_t index = by * blocksAcross_ + bx;
    TIFF* tif = nullptr;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (auto it = cache_.find(index); it != cache_.end()) {
            it->second.lastUse = ++clock_;
            return it->second.values;
        }
        if (!idle_.empty()) {
            tif = idle_.back();
            idle_.pop_back();
        }
    }
    if (!tif && !(tif = openHandle())) {
        fail(path_, "cannot reopen the file");
    }
    auto values = std::make_shared<std::vector<float>>();
    const bool ok = decode(tif, index, *values);
    std::lock_guard<std::mutex> lock(mutex_);
    idle_.push_back(tif);
    if (!ok) {
        fail(path_, std::string("read failed: cannot decode ") + (tiled_ ? "tile " : "strip ") +
                        std::to_string(index));
    }
    const size_t bytes = values->size() * sizeof(float);
    // Evict the least recently used blocks beyond the budget (a block in use stays alive
    // through its shared_ptr).
    while (!cache_.empty() && used_ + bytes > budget_) {
        auto oldest = cache_.begin();
        for (auto it = cache_.begin(); it != cache_.end(); ++it) {
            if (it->second.lastUse < oldest->second.lastUse) {
                oldest = it;
            }
        }
        used_ -= oldest->second.values->size() * sizeof(float);
        cache_.erase(oldest);
    }
    auto [it, inserted] = cache_.try_emplace(index, Entry{values, ++clock_});
    if (inserted) {
        used_ += bytes;
    }
    return it->second.values;
}

namespace {

struct DecompressorDeleter {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// Undoes TIFF's floating-point predictor (Predictor = 3, TIFF Technical Note 3) on one row of
// `count` float32 samples of one channel: the row's bytes are differences from the byte before
// them (a running sum modulo 256 restores them), laid out as planes of the samples' bytes from
// the most significant one down. The samples come out in the host's byte order, whatever the
// file's.
void undoFloatPredictor(uint8_t* bytes, size_t count, float* out) {
    uint8_t sum = 0;
    for (size_t k = 0; k < 4 * count; ++k) {
        sum = static_cast<uint8_t>(sum + bytes[k]);
        bytes[k] = sum;
    }
    const uint8_t* b3 = bytes;             // most significant bytes
    const uint8_t* b2 = bytes + count;
    const uint8_t* b1 = bytes + 2 * count;
    const uint8_t* b0 = bytes + 3 * count; // least significant
    for (size_t i = 0; i < count; ++i) {
        const uint32_t word = static_cast<uint32_t>(b0[i]) | static_cast<uint32_t>(b1[i]) << 8 |
                              static_cast<uint32_t>(b2[i]) << 16 | static_cast<uint32_t>(b3[i]) << 24;
        out[i] = std::bit_cast<float>(word);
    }
}

} // namespace

// Deflate with the floating-point predictor, decoded here rather than by libtiff, whose
// byte-at-a-time undoing of the predictor costs several times the inflation itself: the raw
// block is inflated by libdeflate (TIFF's Deflate is a zlib stream) and the predictor undone
// row by row. False when the block is not what this expects; libtiff then decodes it.
bool TiffBlockReader::decodeFloatPredictorDeflate(TIFF* tif, uint32_t index, uint32_t rows,
                                                  std::vector<float>& values) const {
    const uint64_t rawBytes = TIFFGetStrileByteCount(tif, index);
    if (rawBytes == 0 || rawBytes > (uint64_t{1} << 31)) {
        return false;
    }
    thread_local std::vector<uint8_t> raw, plain;
    raw.resize(static_cast<size_t>(rawBytes));
    const tmsize_t got = tiled_ ? TIFFReadRawTile(tif, index, raw.data(), static_cast<tmsize_t>(raw.size()))
                                : TIFFReadRawStrip(tif, index, raw.data(), static_cast<tmsize_t>(raw.size()));
    if (got != static_cast<tmsize_t>(raw.size())) {
        return false;
    }
    const size_t rowBytes = static_cast<size_t>(blockWidth_) * 4;
    plain.resize(rowBytes * rows);
    thread_local std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> inflater(libdeflate_alloc_decompressor());
    size_t produced = 0;
    if (!inflater || libdeflate_zlib_decompress(inflater.get(), raw.data(), raw.size(), plain.data(), plain.size(),
                                                &produced) != LIBDEFLATE_SUCCESS ||
        produced != plain.size()) {
        return false;
    }
    values.resize(static_cast<size_t>(blockWidth_) * blockHeight_);
    for (uint32_t r = 0; r < rows; ++r) {
        undoFloatPredictor(plain.data() + r * rowBytes, blockWidth_, values.data() + static_cast<size_t>(r) * blockWidth_);
    }
    return true;
}

bool TiffBlockReader::decode(TIFF* tif, uint32_t index, std::vector<float>& values) const {
    if (floatPredictorDeflate_) {
        // Every row of a tile is stored; a strip holds the rows left at the image's bottom.
        const uint32_t rows = tiled_ ? blockHeight_ : std::min(blockHeight_, height_ - (index * blockHeight_));
        if (decodeFloatPredictorDeflate(tif, index, rows, values)) {
            return true;
        }
    }
    const size_t count = static_cast<size_t>(blockWidth_) * blockHeight_;
    std::vector<uint8_t> raw(count * (bits_ / 8));
    const tmsize_t got = tiled_ ? TIFFReadEncodedTile(tif, index, raw.data(), static_cast<tmsize_t>(raw.size()))
                                : TIFFReadEncodedStrip(tif, index, raw.data(), static_cast<tmsize_t>(raw.size()));
    // The last strip may hold fewer rows; missing rows are never read (outside the image).
    if (got < 0) {
        return false;
    }
    values.resize(count);
    const auto convert = [&](auto type) {
        using T = decltype(type);
        for (size_t k = 0; k < count; ++k) {
            T v;
            std::memcpy(&v, raw.data() + k * sizeof(T), sizeof(T));
            values[k] = static_cast<float>(v);
        }
    };
    const bool isSigned = format_ == SAMPLEFORMAT_INT;
    if (format_ == SAMPLEFORMAT_IEEEFP) {
        std::memcpy(values.data(), raw.data(), count * sizeof(float));
    } else if (bits_ == 8) {
        isSigned ? convert(int8_t{}) : convert(uint8_t{});
    } else if (bits_ == 16) {
        isSigned ? convert(int16_t{}) : convert(uint16_t{});
    } else {
        isSigned ? convert(int32_t{}) : convert(uint32_t{});
    }
    return true;
}

} // namespace pyramid
