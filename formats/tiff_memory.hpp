// libtiff over a TIFF held in memory (a tile's blob, or the bytes a tile is written to): the
// stream libtiff reads and writes through, and a handle that owns libtiff's TIFF over it with
// per-handle error and warning handlers. Shared by the TIFF tile codecs (formats/tiff_tile.cpp).
#pragma once
#include <tiffio.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pyramid {

// A TIFF "file" in memory. Reads serve from `data`; writes grow `out`.
struct MemoryStream {
    const uint8_t* data = nullptr;
    size_t size = 0;
    std::vector<uint8_t>* out = nullptr;
    uint64_t pos = 0;
    std::string firstError; // libtiff's first error message, reported in ours
};

// Owns a TIFF handle over a MemoryStream.
class TiffHandle {
public:
    // Opens `stream` in libtiff's `mode` ("r", "rm", "w", ...), with libtiff's single allocations
    // bounded by `maxAlloc` and its errors kept in the stream (get() is null when it fails).
    TiffHandle(MemoryStream& stream, const char* mode, tmsize_t maxAlloc);
    ~TiffHandle() {
        if (tif_) {
            TIFFClose(tif_);
        }
    }
    TiffHandle(const TiffHandle&) = delete;
    TiffHandle& operator=(const TiffHandle&) = delete;
    TIFF* get() const { return tif_; }
    void close() {
        if (tif_) {
            TIFFClose(tif_);
            tif_ = nullptr;
        }
    }

private:
    TIFF* tif_ = nullptr;
};

// `what`, with libtiff's first error on the stream in parentheses when it gave one.
std::string withCause(const std::string& what, const MemoryStream& s);

} // namespace pyramid
