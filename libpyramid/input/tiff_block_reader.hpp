// Single-band TIFF files of 8, 16 or 32-bit integers or float32, compressed or not, striped
// or tiled (whatever libtiff decodes losslessly), decoded one whole strip or tile at a time,
// in parallel (one TIFF handle per reading thread), into a cache of decoded blocks bounded by
// --cache-mb. OpenImageIO's ImageCache decodes such files one scanline at a time under one
// lock per file, through zlib rather than libdeflate: several times slower, and serial.
// Integer values are converted to float32 by value (never normalised).
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "libpyramid/input/raster_info.hpp"

typedef struct tiff TIFF;

namespace pyramid {

class TiffBlockReader {
public:
    // Null when the file is not such a TIFF, or its size is not info's.
    static std::unique_ptr<TiffBlockReader> open(const std::string& path, const RasterInfo& info, int cacheMegabytes);
    ~TiffBlockReader();
    TiffBlockReader(const TiffBlockReader&) = delete;
    TiffBlockReader& operator=(const TiffBlockReader&) = delete;

    // Columns [x0, x1) of rows [y0, y1) into out, row-major. Throws Error on a decoding error.
    // Thread-safe.
    void read(int x0, int y0, int x1, int y1, float* out);

private:
    struct Entry {
        std::shared_ptr<const std::vector<float>> values;
        uint64_t lastUse = 0;
    };

    TiffBlockReader() = default;
    TIFF* openHandle() const;
    std::shared_ptr<const std::vector<float>> get(uint32_t bx, uint32_t by);
    bool decode(TIFF* tif, uint32_t index, std::vector<float>& values) const;
    bool decodeFloatPredictorDeflate(TIFF* tif, uint32_t index, uint32_t rows, std::vector<float>& values) const;

    std::string path_;
    uint32_t width_ = 0, height_ = 0;
    uint32_t blockWidth_ = 0, blockHeight_ = 0, blocksAcross_ = 0;
    uint16_t bits_ = 0, format_ = 1; // SAMPLEFORMAT_UINT
    bool tiled_ = false;
    bool floatPredictorDeflate_ = false; // float32, Deflate, Predictor = 3: decoded here
    size_t budget_ = 0;
    std::mutex mutex_;
    std::vector<TIFF*> idle_;                    // open handles not in use
    std::unordered_map<uint32_t, Entry> cache_; // decoded blocks by index
    size_t used_ = 0;
    uint64_t clock_ = 0;
};

} // namespace pyramid
