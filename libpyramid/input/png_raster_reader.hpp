// PNG inputs decoded with libpng alone (no OpenImageIO): grey, grey + alpha, RGB and RGBA
// images of 8 or 16 bits. PNG has no random access (one Deflate stream for the whole image), so
// the image is decoded once, whole: into memory when it fits the input cache's budget, else row
// by row into a scratch file (scratch_file.hpp) read back by window, so that memory stays
// bounded whatever the image's size (an interlaced image, whose passes need it whole, must fit
// the budget). A non-interlaced image is decoded by a thread of its own, north to south, while
// the caller already reads the rows decoded so far (a read waits for the rows it needs): one
// core decodes while the others work. Samples are the stored values:
// no gamma or colour-profile conversion, alpha not multiplied into colour.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "libpyramid/input/raster_info.hpp"
#include "libpyramid/input/scratch_file.hpp"

namespace pyramid {

class PngRasterReader {
public:
    // Null when the file is not a PNG, or is one of the layouts left to OpenImageIO (palette,
    // grey of fewer than 8 bits, a transparency chunk). Throws Error("PATH: ...") when its
    // header cannot be read, or it is too large to hold; OptionError("cacheMegabytes") for an
    // interlaced image larger than the budget.
    static std::unique_ptr<PngRasterReader> open(const std::string& path, int cacheMegabytes);
    ~PngRasterReader(); // stops the decoding thread, if it still runs

    const RasterInfo& info() const { return info_; }

    // As RasterSource's reads (the window is checked by the caller). Thread-safe. Each waits
    // until rows [y0, y1) are decoded, and throws Error("PATH: cannot read: damaged or
    // truncated PNG (...)") when the image cannot be decoded that far; the last 16 rows come
    // only once the whole file has been read and checked.
    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const;
    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const;
    // 8-bit images only (false otherwise).
    bool readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out, std::ptrdiff_t rowStride) const;

    struct Decoding; // libpng's state (png_raster_reader.cpp)

private:
    PngRasterReader();
    void decodeRows();              // the decoding thread
    void waitForRows(int y1) const; // rows [0, y1) decoded, or throws
    template <typename T>
    const T* rowSpan(int y, int x0, int x1, std::vector<uint8_t>& buffer) const;
    template <typename Out>
    void copyWindow(int x0, int y0, int x1, int y1, int c0, int c1, Out* out) const;

    std::string path_;
    RasterInfo info_;
    // The decoded samples, interleaved, row 0 = north: bytes_ for 8-bit images, words_ for
    // 16-bit ones. Left uninitialised (never read before decoded): zero-filling them first
    // would make the opening thread fault in every page of a large image before decoding.
    std::unique_ptr<uint8_t[]> bytes_;
    std::unique_ptr<uint16_t[]> words_;
    std::unique_ptr<ScratchFile> scratch_; // instead of both, for an image beyond the budget
    size_t rowBytes_ = 0;
    std::unique_ptr<Decoding> decoding_;
    std::thread decoder_;
    std::atomic<int> rowsDecoded_{0}; // rows [0, rowsDecoded_) hold their final samples
    std::atomic<bool> stop_{false};
    mutable std::mutex mutex_;
    mutable std::condition_variable progress_;
    std::string error_; // under mutex_: the message of why decoding stopped short, empty while it goes well
};

} // namespace pyramid
