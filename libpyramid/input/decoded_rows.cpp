#include "libpyramid/input/decoded_rows.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "formats/error.hpp"

namespace pyramid {

namespace {

// Rows published to the readers at once: fewer wake-ups than one by one.
constexpr int kRowsPerStep = 16;
// The rows in memory come in blocks of at most this size (the whole rows it holds; one row when
// a row is larger), each given back on its own once the reads are past it (releaseRowsAbove):
// huge pages (pixel_memory.hpp), and freed blocks the heap can serve the run's next allocations
// from. At most, not at least: each block starts on a huge page, so a block a few bytes over 2 MB
// took two, and the heap's small allocations that fell in the second's rest touched it all (the
// peak was about twice the image: 103 MiB for a 26 MB DTED file, 62 MiB since).
constexpr size_t kChunkBytes = size_t{2} << 20;

// Channels [c0, c1) of `count` interleaved pixels of `channels` samples, each converted to Out
// by value; returns the end of what it wrote.
template <typename T, typename Out>
Out* copyPixels(const T* from, size_t count, int channels, int c0, int c1, Out* out) {
    const size_t n = static_cast<size_t>(channels);
    if (c0 == 0 && c1 == channels) {
        return std::copy(from, from + count * n, out);
    }
    for (size_t x = 0; x < count; ++x, from += n) {
        out = std::copy(from + c0, from + c1, out);
    }
    return out;
}

} // namespace

DecodedRows::DecodedRows(std::string path, const RasterInfo& info, int cacheMegabytes, int heldBack)
    : path_(std::move(path)), info_(info), heldBack_(heldBack) {
    const size_t sampleBytes = info.type == SampleType::UInt8 ? 1 : info.type == SampleType::Float32 ? 4 : 2;
    rowBytes_ = static_cast<size_t>(info.width) * static_cast<size_t>(info.channels) * sampleBytes;
    const size_t budget = static_cast<size_t>(std::max(cacheMegabytes, 1)) << 20;
    if (imageBytes() > budget) {
        scratch_ = std::make_unique<ScratchFile>(path_);
    } else {
        const size_t rowsPerChunk = std::max<size_t>(1, kChunkBytes / std::max<size_t>(rowBytes_, 1));
        chunkRows_ = static_cast<int>(std::clamp<size_t>(rowsPerChunk, 1, static_cast<size_t>(std::max(info.height, 1))));
        for (int y = 0; y < info.height; y += chunkRows_) {
            chunks_.push_back(makePixelMemory(rowBytes_ * static_cast<size_t>(std::min(chunkRows_, info.height - y))));
        }
    }
}

DecodedRows::~DecodedRows() {
    stop_ = true;
    if (thread_.joinable()) {
        thread_.join();
    }
}

void DecodedRows::start(std::unique_ptr<Decoder> decoder) {
    decoder_ = std::move(decoder);
    thread_ = std::thread([this] { decodeAll(); });
}

uint8_t* DecodedRows::rowInMemory(int y) {
    return chunks_[static_cast<size_t>(y / chunkRows_)].get() + static_cast<size_t>(y % chunkRows_) * rowBytes_;
}

void DecodedRows::releaseRowsAbove(int y) {
    if (scratch_) {
        return;
    }
    // Only decoded rows: the decoder may still be writing the ones after. The last block may
    // be short.
    const int rows = std::min(y, rowsDecoded_.load(std::memory_order_acquire));
    const int end = rows >= info_.height ? static_cast<int>(chunks_.size()) : rows / chunkRows_;
    const std::lock_guard<std::mutex> lock(mutex_);
    for (; released_ < end; ++released_) {
        chunks_[static_cast<size_t>(released_)].reset();
    }
}

size_t DecodedRows::bytesHeld() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    size_t bytes = 0;
    for (size_t k = static_cast<size_t>(released_); k < chunks_.size(); ++k) {
        bytes += chunks_[k].get_deleter().bytes;
    }
    return bytes;
}

void DecodedRows::markDecoded() { rowsDecoded_ = info_.height; }

void DecodedRows::publish(int rows, const std::string& error) {
    bool wake = false;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        rowsDecoded_.store(rows, std::memory_order_release);
        error_ = error;
        // The last rows or an error end every wait; otherwise a wait ends when its rows are in.
        wake = rows >= awaited_ || rows == info_.height || !error.empty();
        if (wake) {
            awaited_ = INT_MAX; // the readers still short of rows say so again
        }
    }
    if (wake) {
        progress_.notify_all();
    }
}

void DecodedRows::decodeAll() {
    const int height = info_.height;
    std::vector<uint8_t> row(scratch_ ? rowBytes_ : 0); // a row on its way to the scratch file
    try {
        for (int y = 0; y < height && !stop_; ++y) {
            if (scratch_) {
                decoder_->readRow(row.data());
                scratch_->write(static_cast<uint64_t>(y) * rowBytes_, row.data(), rowBytes_);
            } else {
                decoder_->readRow(rowInMemory(y));
            }
            if ((y + 1) % kRowsPerStep == 0 && y + 1 < height - heldBack_) {
                publish(y + 1, "");
            }
        }
        if (stop_) {
            return;
        }
        decoder_->finish();
    } catch (const Error& e) {
        publish(rowsDecoded_.load(std::memory_order_relaxed), e.what());
        return;
    }
    decoder_.reset(); // the file closed as soon as it is read
    publish(height, "");
}

void DecodedRows::waitForRows(int y1) const {
    if (rowsDecoded_.load(std::memory_order_acquire) >= y1) {
        return;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    while (rowsDecoded_.load(std::memory_order_acquire) < y1 && error_.empty()) {
        awaited_ = std::min(awaited_, y1);
        progress_.wait(lock);
    }
    if (rowsDecoded_.load(std::memory_order_acquire) < y1) {
        throw Error(error_);
    }
}

// Columns [x0, x1) of row y, every channel, as T: in memory, or read from the scratch file
// into `buffer`.
template <typename T>
const T* DecodedRows::rowSpan(int y, int x0, int x1, std::vector<uint8_t>& buffer) const {
    const size_t pixelBytes = static_cast<size_t>(info_.channels) * sizeof(T);
    const size_t offset = static_cast<size_t>(y) * rowBytes_ + static_cast<size_t>(x0) * pixelBytes;
    if (!scratch_) {
        const uint8_t* chunk = chunks_[static_cast<size_t>(y / chunkRows_)].get();
        if (chunk == nullptr) {
            throw std::logic_error(path_ + ": row " + std::to_string(y) + " read after it was released");
        }
        return reinterpret_cast<const T*>(chunk + static_cast<size_t>(y % chunkRows_) * rowBytes_ +
                                          static_cast<size_t>(x0) * pixelBytes);
    }
    buffer.resize(static_cast<size_t>(x1 - x0) * pixelBytes);
    scratch_->read(offset, buffer.data(), buffer.size());
    return reinterpret_cast<const T*>(buffer.data());
}

template <typename Out>
void DecodedRows::copyWindow(int x0, int y0, int x1, int y1, int c0, int c1, Out* out) const {
    waitForRows(y1);
    thread_local std::vector<uint8_t> buffer;
    const size_t count = static_cast<size_t>(x1 - x0);
    for (int y = y0; y < y1; ++y) {
        switch (info_.type) {
        case SampleType::UInt8:
            out = copyPixels(rowSpan<uint8_t>(y, x0, x1, buffer), count, info_.channels, c0, c1, out);
            break;
        case SampleType::Float32:
            if constexpr (std::is_same_v<Out, float>) {
                out = copyPixels(rowSpan<float>(y, x0, x1, buffer), count, info_.channels, c0, c1, out);
            }
            break;
        case SampleType::Int16:
            if constexpr (std::is_same_v<Out, float>) {
                out = copyPixels(rowSpan<int16_t>(y, x0, x1, buffer), count, info_.channels, c0, c1, out);
            }
            break;
        default:
            out = copyPixels(rowSpan<uint16_t>(y, x0, x1, buffer), count, info_.channels, c0, c1, out);
        }
    }
}

void DecodedRows::readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const {
    copyWindow(x0, y0, x1, y1, channel, channel + 1, out);
}

void DecodedRows::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const {
    if (info_.type == SampleType::Float32 || info_.type == SampleType::Int16) {
        fail(path_, std::string("holds ") + (info_.type == SampleType::Int16 ? "signed 16-bit" : "float32") +
                        " values, not 8 or 16-bit colours");
    }
    copyWindow(x0, y0, x1, y1, c0, c1, out);
}

bool DecodedRows::readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out,
                            std::ptrdiff_t rowStride) const {
    if (info_.type != SampleType::UInt8) {
        return false;
    }
    waitForRows(y1);
    thread_local std::vector<uint8_t> buffer;
    const size_t channels = static_cast<size_t>(info_.channels);
    const size_t wanted = static_cast<size_t>(c1 - c0);
    for (int y = y0; y < y1; ++y) {
        const uint8_t* from = rowSpan<uint8_t>(y, x0, x1, buffer);
        uint8_t* to = out + static_cast<std::ptrdiff_t>(y - y0) * rowStride;
        if (wanted == channels) {
            std::memcpy(to, from, static_cast<size_t>(x1 - x0) * channels);
            continue;
        }
        for (int x = x0; x < x1; ++x, from += channels, to += wanted) {
            std::memcpy(to, from + c0, wanted);
        }
    }
    return true;
}

} // namespace pyramid
