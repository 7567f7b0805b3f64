// TiffBlockReader's decoding of one block into the interleaved samples the cache holds: the
// file's chunk as libtiff decodes it, Deflate with the floating-point predictor inflated here,
// and the blocks whose chunks are not those samples assembled from them: bands stored in
// separate planes (one chunk per band, interleaved here) and palette indices (widened to their
// colours).
#include <libdeflate.h>
#include <tiffio.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/tiff_block_reader.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"
#include "libpyramid/input/tiff_samples.hpp"

namespace pyramid {

namespace {

struct DecompressorDeleter {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

} // namespace

// Deflate with the floating-point predictor, decoded here rather than by libtiff, whose
// byte-at-a-time undoing of the predictor costs several times the inflation itself: the raw
// block is inflated by libdeflate (TIFF's Deflate is a zlib stream) and the predictor undone
// row by row. False when the block is not what this expects; libtiff then decodes it.
bool TiffBlockReader::decodeFloatPredictorDeflate(TIFF* tif, uint32_t index, uint32_t rows,
                                                  std::vector<uint8_t>& bytes) const {
    const uint64_t rawBytes = TIFFGetStrileByteCount(tif, index);
    // Deflate never grows data by more than a few bytes per 16 KB: a larger count is damage,
    // which libtiff's own path then reports, without this allocating it.
    const uint64_t plainBytes = static_cast<uint64_t>(blockWidth_) * rows * 4;
    if (rawBytes == 0 || rawBytes > plainBytes + plainBytes / 64 + 4096) {
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
    bytes.resize(rowBytes * blockHeight_);
    for (uint32_t r = 0; r < rows; ++r) {
        undoFloatPredictor(plain.data() + r * rowBytes, blockWidth_, bytes.data() + r * rowBytes);
    }
    return true;
}

void TiffBlockReader::decode(TIFF* tif, uint32_t index, std::vector<uint8_t>& bytes) const {
    if (planes_ > 1 || !palette_.empty()) {
        decodeAssembled(tif, index, bytes);
    } else {
        decodeChunk(tif, index, bytes);
    }
}

void TiffBlockReader::decodeAssembled(TIFF* tif, uint32_t index, std::vector<uint8_t>& bytes) const {
    const size_t pixels = static_cast<size_t>(blockWidth_) * blockHeight_;
    const size_t sampleBytes = bits_ / 8u;
    thread_local std::vector<uint8_t> chunk;
    chunk.resize(pixels * sampleBytes);
    if (!palette_.empty()) {
        decodeChunk(tif, index, chunk);
        for (size_t i = 0; i < pixels; ++i) {
            std::memcpy(bytes.data() + 3 * i, palette_.data() + 3 * static_cast<size_t>(chunk[i]), 3);
        }
        return;
    }
    // Plane p's samples go to every pixel's sample p. The last strip's missing rows (below the
    // image) are left as they are: never read.
    for (uint32_t p = 0; p < planes_; ++p) {
        decodeChunk(tif, index + p * chunksPerPlane_, chunk);
        uint8_t* to = bytes.data() + p * sampleBytes;
        const uint8_t* from = chunk.data();
        const size_t stride = pixelBytes();
        if (sampleBytes == 1) {
            for (size_t i = 0; i < pixels; ++i) {
                to[i * stride] = from[i];
            }
        } else {
            for (size_t i = 0; i < pixels; ++i) {
                std::memcpy(to + i * stride, from + i * sampleBytes, sampleBytes);
            }
        }
    }
}

void TiffBlockReader::decodeChunk(TIFF* tif, uint32_t index, std::vector<uint8_t>& bytes) const {
    if (!strileInFile(tif, index)) {
        fail(path_, std::string("damaged TIFF: ") + (tiled_ ? "tile " : "strip ") + std::to_string(index) +
                        " lies beyond the end of the file");
    }
    if (floatPredictorDeflate_) {
        // Every row of a tile is stored; a strip holds the rows left at the image's bottom.
        const uint32_t rows = tiled_ ? blockHeight_ : std::min(blockHeight_, height_ - (index * blockHeight_));
        if (decodeFloatPredictorDeflate(tif, index, rows, bytes)) {
            return;
        }
    }
    // Decoded in place, as libtiff gives the samples: host order, predictors undone.
    const auto size = static_cast<tmsize_t>(bytes.size());
    if (jpeg_) {
        takeJpegWarning(); // none of an earlier block's
    }
    const tmsize_t got = tiled_ ? TIFFReadEncodedTile(tif, index, bytes.data(), size)
                                : TIFFReadEncodedStrip(tif, index, bytes.data(), size);
    // The last strip may hold fewer rows; missing rows are never read (outside the image).
    if (got < 0) {
        fail(path_, std::string("read failed: cannot decode ") + (tiled_ ? "tile " : "strip ") + std::to_string(index));
    }
    failOnJpegWarning(std::string(tiled_ ? "tile " : "strip ") + std::to_string(index));
}

// libjpeg decodes corrupt data on, warning once: the block is refused rather than used.
void TiffBlockReader::failOnJpegWarning(const std::string& where) const {
    if (jpeg_) {
        const std::string warning = takeJpegWarning();
        if (!warning.empty()) {
            fail(path_, "damaged JPEG data in " + where + ": " + warning);
        }
    }
}

} // namespace pyramid
