// Uncompressed, striped TIFF files of interleaved 8- or 16-bit unsigned or 32-bit float samples
// (what OpenImageIO, GDAL and most tools write for large imagery and DEMs without compression),
// read without OpenImageIO's ImageCache, which decodes such files one scanline at a time under
// one lock per file and copies every sample through its tiles. The samples are the file's values,
// as the cache returns them.
//
// A wide window is read a row at a time, each row one pread at its offset in the file, straight
// from the operating system's page cache, from any number of threads. A narrow and tall window
// (a pyramid's footprint of a few hundred pixels: a pread for each of its short rows costs more
// in system calls than in copying) is copied from blocks of kBlockRows rows, read once and kept
// for the windows beside and below it: whole rows when the whole-row blocks under the first
// such window take at most half the budget (the windows of a row of footprints share them; rows
// that follow each other in the file are read in one call), else columns of kChunkBytes a row.
// The least recently used blocks go once they pass the reader's budget (kCacheBytes, or less for
// the members of a mosaic: `--cache-mb` shared by its open files); a window whose blocks would
// take more than half the budget is read row by row, as its blocks would not stay for the next.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>
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
    // Its blocks take at most min(kCacheBytes, cacheBytes).
    static std::unique_ptr<TiffPixelReader> open(const std::string& path, int width, int height, int channels,
                                                 int bytesPerSample, bool floatSamples, size_t cacheBytes);
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

    static constexpr int kBlockRows = 16;
    static constexpr uint64_t kNarrowRowBytes = 16 << 10;
    static constexpr size_t kChunkBytes = 8 << 10;
    static constexpr size_t kCacheBytes = 16 << 20;

private:
    struct Block {
        std::once_flag once;
        std::unique_ptr<uint8_t[]> bytes; // the block's rows, `stride` bytes each (blockBytes_ held)
        size_t stride = 0;
        bool ok = false;
        int error = 0; // errno of a failed read (0: the file is short)
    };

    TiffPixelReader() = default;
    uint64_t rowOffset(int y) const;
    // Chooses the blocks' columns at the first narrow, tall window, `windowRows` tall.
    void shapeBlocks(int windowRows) const;
    bool throughBlocks(int x0, int y0, int x1, int y1) const;
    std::shared_ptr<Block> block(int by, int bx) const;
    void load(Block& b, int by, int bx) const;
    // take(y, x, samples, n): the n pixels from column x of row y, for every row of the window,
    // from blocks (forEachPiece, a row possibly in pieces) or a pread per row.
    bool forEachPiece(int x0, int y0, int x1, int y1,
                      const std::function<void(int, int, const uint8_t*, size_t)>& take) const;
    bool forEachRow(int x0, int y0, int x1, int y1,
                    const std::function<void(int, int, const uint8_t*, size_t)>& take) const;

    int fd_ = -1;
    int width_ = 0, height_ = 0, channels_ = 0, bytesPerSample_ = 0;
    bool float_ = false;
    uint32_t rowsPerStrip_ = 0;
    size_t pixelBytes_ = 0;
    uint64_t rowBytes_ = 0;
    std::vector<uint64_t> stripOffsets_;
    mutable std::once_flag shaped_;
    mutable int blockColumns_ = 1, blocksAcross_ = 1;
    mutable size_t blockBytes_ = 0;
    size_t cacheBytes_ = 0;
    mutable std::mutex cacheMutex_;
    mutable std::list<uint64_t> recent_; // most recent first
    mutable std::unordered_map<uint64_t, std::pair<std::shared_ptr<Block>, std::list<uint64_t>::iterator>> cache_;
    mutable size_t cachedBytes_ = 0;
    // The buffers of blocks that went while no reader held them, for the next blocks: their
    // pages are already mapped (a fresh buffer's page faults cost as much as the reads saved).
    mutable std::vector<std::unique_ptr<uint8_t[]>> spare_;
};

} // namespace pyramid
