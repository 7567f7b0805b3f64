// TIFF files of 8, 16 or 32-bit integers or float32, one band or several interleaved (grey,
// grey and alpha, RGB, RGBA), compressed or not, striped or tiled, BigTIFF or not (whatever
// libtiff decodes losslessly), in memory bounded by the cache budget whatever the file's size
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
// OpenImageIO's ImageCache decodes such files one scanline at a time under one lock per file,
// through zlib rather than libdeflate: several times slower, and serial. Integer values are
// converted to float32 by value (never normalised).
#pragma once
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

private:
    TiffBlockReader() = default;
    TIFF* openHandle() const;
    void readBlocks(int x0, int y0, int x1, int y1, int c0, int c1, float* out);
    void decode(TIFF* tif, uint32_t index, std::vector<float>& values) const;
    bool decodeFloatPredictorDeflate(TIFF* tif, uint32_t index, uint32_t rows, std::vector<float>& values) const;

    std::string path_;
    uint32_t width_ = 0, height_ = 0;
    uint32_t blockWidth_ = 0, blockHeight_ = 0, blocksAcross_ = 0;
    uint32_t channels_ = 1; // interleaved samples per pixel, in blocks and scratch rows alike
    uint16_t bits_ = 0, format_ = 1; // SAMPLEFORMAT_UINT
    bool tiled_ = false;
    bool floatPredictorDeflate_ = false; // float32, Deflate, Predictor = 3: decoded here
    std::unique_ptr<BlockCache> cache_;   // blocks within the budget
    std::unique_ptr<ScratchFile> rows_;   // or the whole image, float32 rows, for huge strips
    std::once_flag spilled_;              // rows_ filled
    std::mutex mutex_;
    std::vector<TIFF*> idle_;             // open handles not in use
};

} // namespace pyramid
