// An image that can only be decoded from its start (PNG, JPEG: no random access), decoded
// once, whole, north to south: into memory when it fits the input cache's budget, else row by
// row into a scratch file (scratch_file.hpp) read back by window, so that memory stays bounded
// whatever the image's size. A thread of its own decodes while the caller already reads the
// rows decoded so far (a read waits for the rows it needs): one core decodes while the others
// work. In memory, the rows come in blocks of at most 2 MB, given back once the reads are past them
// (releaseRowsAbove). The last rows are held back until the decoder has read and checked the
// rest of the file, so that a damaged end fails the reads that would have used it. Samples are
// interleaved 8 or 16-bit values, int16 (DTED's heights) or float32 (an ASCII grid's), host
// order, row 0 north. The
// formats' readers (png_raster_reader.hpp, jpeg_raster_reader.hpp, ascii_grid_reader.hpp,
// dted_reader.hpp) only decode.
#pragma once
#include <atomic>
#include <climits>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "libpyramid/filters/pixel_memory.hpp"
#include "libpyramid/input/raster_info.hpp"
#include "libpyramid/input/scratch_file.hpp"

namespace pyramid {

class DecodedRows {
public:
    // What a format's reader gives: its rows, in order. Each call may throw Error("PATH: ...")
    // for a damaged file; the reads then fail with that message.
    class Decoder {
    public:
        virtual ~Decoder() = default;
        virtual void readRow(uint8_t* row) = 0; // the next row's samples
        virtual void finish() = 0;              // after the last row: the rest of the file
    };

    // An image of `info` (UInt8, UInt16, Int16 or Float32 samples) of which the last `heldBack`
    // rows are published only once the decoder has finished. Held in memory when it fits
    // `cacheMegabytes`, else in a scratch file.
    DecodedRows(std::string path, const RasterInfo& info, int cacheMegabytes, int heldBack);
    ~DecodedRows(); // stops the decoding thread, if it still runs
    DecodedRows(const DecodedRows&) = delete;
    DecodedRows& operator=(const DecodedRows&) = delete;

    const RasterInfo& info() const { return info_; }
    size_t imageBytes() const { return rowBytes_ * static_cast<size_t>(info_.height); }
    bool inMemory() const { return !scratch_; }

    // Decodes every row on a thread of its own, from now on.
    void start(std::unique_ptr<Decoder> decoder);
    // For formats that decode the whole image at once (an interlaced PNG; in memory only): the
    // place of row y, and then the whole image marked decoded.
    uint8_t* rowInMemory(int y);
    void markDecoded();

    // As RasterSource's reads (the window is checked by the caller). Thread-safe. Each waits
    // until rows [y0, y1) are decoded, and throws the decoder's Error when the image cannot be
    // decoded that far.
    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const;
    // Not of int16 or float32 samples (fail).
    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const;
    // 8-bit images only (false otherwise).
    bool readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out, std::ptrdiff_t rowStride) const;

    // Rows [0, y) will not be read again: in memory, the blocks of rows wholly above y that are
    // decoded are given back, for the run's next allocations to reuse. A read of such a row is
    // then an error (std::logic_error). Thread-safe; a scratch file keeps its rows.
    void releaseRowsAbove(int y);
    size_t bytesHeld() const; // the decoded samples' memory not given back

private:
    void decodeAll();               // the decoding thread
    void publish(int rows, const std::string& error);
    void waitForRows(int y1) const; // rows [0, y1) decoded, or throws
    template <typename T>
    const T* rowSpan(int y, int x0, int x1, std::vector<uint8_t>& buffer) const;
    template <typename Out>
    void copyWindow(int x0, int y0, int x1, int y1, int c0, int c1, Out* out) const;

    std::string path_;
    RasterInfo info_;
    int heldBack_;
    size_t rowBytes_ = 0;
    // The decoded samples, left uninitialised (never read before decoded): zero-filling them
    // first would make the opening thread fault in every page of a large image before decoding.
    // In blocks of chunkRows_ rows (at most 2 MB, or one row), each given back on its own (releaseRowsAbove).
    std::vector<PixelMemory> chunks_;
    int chunkRows_ = 1;
    int released_ = 0; // under mutex_: chunks [0, released_) are given back
    std::unique_ptr<ScratchFile> scratch_; // instead, for an image beyond the budget
    std::unique_ptr<Decoder> decoder_;
    std::thread thread_;
    std::atomic<int> rowsDecoded_{0}; // rows [0, rowsDecoded_) hold their final samples
    std::atomic<bool> stop_{false};
    mutable std::mutex mutex_;
    mutable std::condition_variable progress_;
    std::string error_; // under mutex_: why decoding stopped short, empty while it goes well
    // Under mutex_: the fewest rows a waiting read needs (INT_MAX: none waits). The decoder wakes
    // the readers when they have them, not every few rows.
    mutable int awaited_ = INT_MAX;
};

} // namespace pyramid
