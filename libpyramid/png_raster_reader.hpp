// PNG inputs decoded with libpng alone (no OpenImageIO): grey, grey + alpha, RGB and RGBA
// images of 8 or 16 bits. PNG has no random access (one Deflate stream for the whole image),
// so the image is decoded once, whole, when opened, as OpenImageIO's PNG reader does too; a
// PNG input therefore takes width x height x channels x (1 or 2) bytes of memory. Samples are
// the stored values: no gamma or colour-profile conversion, alpha not multiplied into colour.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/raster_source.hpp"

namespace pyramid {

class PngRasterReader {
public:
    // Null when the file is not a PNG, or is one of the layouts left to OpenImageIO (palette,
    // grey of fewer than 8 bits, a transparency chunk). Throws Error("PATH: ...") when it is
    // a PNG libpng cannot decode (truncated, corrupt), or too large to hold.
    static std::unique_ptr<PngRasterReader> open(const std::string& path);

    const RasterInfo& info() const { return info_; }

    // As RasterSource's reads (the window is checked by the caller). Thread-safe.
    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const;
    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const;
    // 8-bit images only (false otherwise).
    bool readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out, std::ptrdiff_t rowStride) const;

private:
    PngRasterReader() = default;
    RasterInfo info_;
    std::vector<uint8_t> bytes_;   // 8-bit images, interleaved, row 0 = north
    std::vector<uint16_t> words_;  // 16-bit images
};

} // namespace pyramid
