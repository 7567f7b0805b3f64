// TIFF files of 8, 16 or 32-bit integers, float32 or float64 (read as float32, to the nearest:
// OpenImageIO 2.4 reads tiled float64 as zeros), one band or several (grey, grey and alpha,
// RGB, RGBA; interleaved, or in separate planes within the cache), or 8-bit palette indices
// (widened to their RGB colours), compressed or not, striped or tiled, BigTIFF or not (whatever
// libtiff decodes losslessly, LERC, WebP, and JPEG of 8-bit samples, YCbCr decoded to RGB by
// libjpeg as OpenImageIO decodes it), in memory bounded by the cache budget whatever the file's size
// and layout:
// * strips and tiles up to a quarter of the budget are decoded one whole block at a time, in
//   parallel (one TIFF handle per reading thread), into the shared block cache
//   (block_cache.hpp: recycled buffers, one decode per block however many threads want it);
// * larger strips (a whole image in one strip, say) are decoded once, row by row
//   (tiff_strip_stream.hpp), at the first read, into a scratch file (scratch_file.hpp) read
//   back by window;
// * larger tiles cannot be decoded piecewise: the file is refused, naming the cache they need.
// Blocks are checked against the image before anything is allocated: a file declaring tiles
// far larger than its image is refused as damaged.
// Blocks and scratch rows hold the samples as decoded, in the file's own type (an 8-bit image
// takes a quarter of the memory float32 would, so a budget holds four times its pixels); reads
// convert them: to float32 by value (integers are never normalised), to 16-bit values, or, for
// 8-bit samples, not at all.
// OpenImageIO's ImageCache decodes such files one scanline at a time under one lock per file,
// through zlib rather than libdeflate: several times slower, and serial.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "libpyramid/input/block_cache.hpp"
#include "libpyramid/input/raster_info.hpp"
#include "libpyramid/input/scratch_file.hpp"

typedef struct tiff TIFF;

namespace pyramid {

class TiffBlockReader {
public:
    // Null when the file is not such a TIFF, or its size is not info's. Throws Error for blocks
    // no image of its size has, and OptionError("cacheMegabytes") for tiles beyond the budget.
    static std::unique_ptr<TiffBlockReader> open(const std::string& path, const RasterInfo& info, int cacheMegabytes);
    ~TiffBlockReader();
    TiffBlockReader(const TiffBlockReader&) = delete;
    TiffBlockReader& operator=(const TiffBlockReader&) = delete;

    // Channels [c0, c1) of columns [x0, x1) of rows [y0, y1) into out, interleaved, row-major,
    // as float32 by value. Throws Error on a decoding error. Thread-safe.
    void read(int x0, int y0, int x1, int y1, int c0, int c1, float* out);
    // The same as 16-bit values, of a file of 8 or 16-bit unsigned samples (8-bit ones widened
    // exactly).
    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out);
    // The same as stored, of a file of 8-bit unsigned samples; row y goes to
    // out + (y - y0) * rowStride (bytes; negative to store the rows bottom up).
    void readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out, std::ptrdiff_t rowStride);

private:
    TiffBlockReader() = default;
    TIFF* openHandle() const;
    // The reads above: row y of the window goes to out + (y - y0) * rowStride (elements of T).
    template <typename T>
    void readAs(int x0, int y0, int x1, int y1, int c0, int c1, T* out, std::ptrdiff_t rowStride);
    template <typename T>
    void readBlocks(int x0, int y0, int x1, int y1, int c0, int c1, T* out, std::ptrdiff_t rowStride);
    // `pixels` decoded pixels at `from`, channels [c0, c0 + wanted) of each, converted to T.
    template <typename T>
    void convertPixels(const uint8_t* from, size_t pixels, size_t c0, size_t wanted, T* to) const;
    // Block `index` (the chunk index of the first plane) as the cache holds it: interleaved
    // samples, palette indices widened.
    void decode(TIFF* tif, uint32_t index, std::vector<uint8_t>& bytes) const;
    // Chunk `chunk` as libtiff decodes it (or decodeFloatPredictorDeflate), into `bytes`.
    void decodeChunk(TIFF* tif, uint32_t chunk, std::vector<uint8_t>& bytes) const;
    // A block assembled from its planes' chunks, or widened from its palette indices.
    void decodeAssembled(TIFF* tif, uint32_t index, std::vector<uint8_t>& bytes) const;
    void failOnJpegWarning(const std::string& where) const;
    bool decodeFloatPredictorDeflate(TIFF* tif, uint32_t index, uint32_t rows, std::vector<uint8_t>& bytes) const;
    size_t pixelBytes() const { return static_cast<size_t>(channels_) * (bits_ / 8u); }

    std::string path_;
    uint32_t width_ = 0, height_ = 0;
    uint32_t blockWidth_ = 0, blockHeight_ = 0, blocksAcross_ = 0;
    uint32_t channels_ = 1; // interleaved samples per pixel, in blocks and scratch rows alike
    uint32_t planes_ = 1;   // chunks per block: the bands of a file of separate planes
    uint32_t chunksPerPlane_ = 0;
    std::vector<uint8_t> palette_; // RGB per index, for a file of palette indices (else empty)
    uint16_t bits_ = 0, format_ = 1; // SAMPLEFORMAT_UINT
    bool tiled_ = false;
    bool floatPredictorDeflate_ = false; // float32, Deflate, Predictor = 3: decoded here
    bool jpeg_ = false;                  // JPEG: libjpeg's warnings are errors (failOnJpegWarning)
    bool ycbcrJpeg_ = false;             // JPEG stored as YCbCr: decoded to RGB
    std::unique_ptr<BlockCache> cache_;   // blocks within the budget
    std::unique_ptr<ScratchFile> rows_;   // or the whole image's decoded rows, for huge strips
    std::once_flag spilled_;              // rows_ filled
    std::mutex mutex_;
    std::vector<TIFF*> idle_;             // open handles not in use
};

} // namespace pyramid
