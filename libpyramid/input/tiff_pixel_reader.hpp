// Uncompressed, striped TIFF files of interleaved 8- or 16-bit unsigned or 32-bit float samples
// (what OpenImageIO, GDAL and most tools write for large imagery and DEMs without compression),
// read without
// OpenImageIO's ImageCache: each row of a window is one pread at its offset in the file.
// The cache decodes such files one scanline at a time under one lock per file and copies every
// sample through its tiles; the operating system's page cache serves these reads directly, from
// any number of threads. The samples are the file's values, as the cache returns them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

typedef struct tiff TIFF;

namespace pyramid {

// Opens a TIFF input with libtiff in `mode` ("r", or "rm" without memory mapping), its errors
// and warnings silenced: a file libtiff cannot read is left to OpenImageIO, whose message names
// the problem, and GeoTIFF tags libtiff does not know are no concern. Null when it fails.
// With `noteJpegWarnings`, the warnings libjpeg gives through libtiff (corrupt JPEG data, which
// libjpeg decodes on regardless) are kept instead, for takeJpegWarning.
TIFF* openTiffQuietly(const std::string& path, const char* mode, bool noteJpegWarnings = false);
// The first JPEG warning noted on this thread since the last call (empty if none), cleared.
std::string takeJpegWarning();

// Whether strip or tile `index` of `tif` (its offset and byte count) lies within the file, whose
// size fstat gives. libtiff's own reading of a block that does not (an offset near 2^63 in a
// damaged BigTIFF, which the read refuses outright) writes before its buffer: readers check each
// block before libtiff reads it.
bool strileInFile(TIFF* tif, uint32_t index);

// For a file that other code will read through libtiff (OpenImageIO): "" when it is not a TIFF
// or every block of its first image lies within the file, else the problem ("damaged TIFF: tile
// 3 lies beyond the end of the file").
std::string tiffBlockBeyondTheFile(const std::string& path);

class TiffPixelReader {
public:
    // nullptr when the file is not such a TIFF (any other layout is left to the cache), or
    // does not match the expected size, channel count and sample type (unsigned integers of 1
    // or 2 bytes, or float32 when `floatSamples`).
    static std::unique_ptr<TiffPixelReader> open(const std::string& path, int width, int height, int channels,
                                                 int bytesPerSample, bool floatSamples = false);
    ~TiffPixelReader();
    TiffPixelReader(const TiffPixelReader&) = delete;
    TiffPixelReader& operator=(const TiffPixelReader&) = delete;

    // Channels [c0, c1) of columns [x0, x1) x rows [y0, y1), interleaved, north first, widened
    // to uint16 by value. False on a read error or a short file (errno set, 0 when short).
    // Thread-safe.
    bool readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const;
    // Float32 files only: channel `channel` of the window, row-major, north first, the file's
    // bits as they are.
    bool readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const;
    // 8-bit files only: the samples as stored, row y at out + (y - y0) * rowStride bytes.
    bool readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out, std::ptrdiff_t rowStride) const;

private:
    TiffPixelReader() = default;
    int fd_ = -1;
    int width_ = 0, channels_ = 0, bytesPerSample_ = 0;
    bool float_ = false;
    uint32_t rowsPerStrip_ = 0;
    std::vector<uint64_t> stripOffsets_;
};

} // namespace pyramid
