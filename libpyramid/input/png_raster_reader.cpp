#include "libpyramid/input/png_raster_reader.hpp"

#include <png.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstring>

#include "formats/error.hpp"

namespace pyramid {

// Everything the decoder touches after setjmp lives here, behind a pointer that does not
// change: a longjmp out of libpng leaves it in a defined state.
struct PngRasterReader::Decoding {
    FILE* file = nullptr;
    png_structp png = nullptr;
    png_infop pngInfo = nullptr;
    std::string error;
    std::vector<png_bytep> rows;
    std::vector<png_byte> scratchRow; // a row on its way to the scratch file

    ~Decoding() {
        if (png) {
            png_destroy_read_struct(&png, pngInfo ? &pngInfo : nullptr, nullptr);
        }
        if (file) {
            std::fclose(file);
        }
    }
};

namespace {

// Rows published to the readers at once: fewer wake-ups than one by one.
constexpr int kRowsPerStep = 16;

[[noreturn]] void onPngError(png_structp png, png_const_charp message) {
    auto* d = static_cast<PngRasterReader::Decoding*>(png_get_error_ptr(png));
    d->error = message ? message : "decoding error";
    png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

std::string damaged(const std::string& why) { return "cannot read: damaged or truncated PNG (" + why + ")"; }

} // namespace

PngRasterReader::PngRasterReader() = default;

PngRasterReader::~PngRasterReader() {
    stop_ = true;
    if (decoder_.joinable()) {
        decoder_.join();
    }
}

std::unique_ptr<PngRasterReader> PngRasterReader::open(const std::string& path, int cacheMegabytes) {
    std::unique_ptr<PngRasterReader> reader(new PngRasterReader());
    reader->path_ = path;
    reader->decoding_ = std::make_unique<Decoding>();
    Decoding* d = reader->decoding_.get();
    d->file = std::fopen(path.c_str(), "rb");
    if (!d->file) {
        return nullptr; // the caller's readers report it
    }
    png_byte signature[8] = {};
    if (std::fread(signature, 1, sizeof signature, d->file) != sizeof signature ||
        png_sig_cmp(signature, 0, sizeof signature) != 0) {
        return nullptr;
    }
    d->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, d, onPngError, onPngWarning);
    if (!d->png || !(d->pngInfo = png_create_info_struct(d->png))) {
        fail(path, "cannot read: out of memory");
    }
    // From here a libpng error comes back to this point with d->error set.
    if (setjmp(png_jmpbuf(d->png))) {
        fail(path, damaged(d->error));
    }
    png_init_io(d->png, d->file);
    png_set_sig_bytes(d->png, sizeof signature);
#ifdef PNG_IGNORE_ADLER32
    // Every chunk's CRC is still checked, over the compressed bytes, so that damage is still
    // found; the zlib stream's own checksum over the decoded bytes would only repeat it, at a
    // tenth of the decoding thread's time.
    png_set_option(d->png, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
#endif
    // A bad CRC fails the file in every chunk, not only the critical ones (libpng's default warns
    // and drops an ancillary chunk): a damaged file is refused whole.
    png_set_crc_action(d->png, PNG_CRC_DEFAULT, PNG_CRC_ERROR_QUIT);
    png_read_info(d->png, d->pngInfo);
    const png_uint_32 width = png_get_image_width(d->png, d->pngInfo);
    const png_uint_32 height = png_get_image_height(d->png, d->pngInfo);
    const int depth = png_get_bit_depth(d->png, d->pngInfo);
    const int colour = png_get_color_type(d->png, d->pngInfo);
    const int channels = colour == PNG_COLOR_TYPE_GRAY         ? 1
                         : colour == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                         : colour == PNG_COLOR_TYPE_RGB        ? 3
                         : colour == PNG_COLOR_TYPE_RGB_ALPHA  ? 4
                                                               : 0;
    if (channels == 0 || (depth != 8 && depth != 16) || png_get_valid(d->png, d->pngInfo, PNG_INFO_tRNS)) {
        return nullptr; // expanded by OpenImageIO's rules instead
    }
    if (depth == 16) {
        png_set_swap(d->png); // PNG is big-endian; the samples are kept as host integers
    }
    const bool interlaced = png_set_interlace_handling(d->png) > 1;
    png_read_update_info(d->png, d->pngInfo);

    const size_t rowSamples = static_cast<size_t>(width) * static_cast<size_t>(channels);
    const size_t samples = rowSamples * height;
    if (height > 0x7fffffffu || width > 0x7fffffffu || samples / height != rowSamples ||
        samples > (size_t{1} << 40)) {
        fail(path, "cannot read: a " + std::to_string(width) + " x " + std::to_string(height) +
                       " PNG is too large to decode in memory; convert it to a tiled TIFF");
    }
    RasterInfo& info = reader->info_;
    info.width = static_cast<int>(width);
    info.height = static_cast<int>(height);
    info.channels = channels;
    info.type = depth == 8 ? SampleType::UInt8 : SampleType::UInt16;
    info.formatName = "png";
    reader->rowBytes_ = rowSamples * static_cast<size_t>(depth / 8);
    const size_t budget = static_cast<size_t>(std::max(cacheMegabytes, 1)) << 20;
    if (reader->rowBytes_ * height > budget) {
        // Larger than the cache: decoded row by row into a scratch file, read back by window.
        const size_t megabytes = (reader->rowBytes_ * height + (size_t{1} << 20) - 1) >> 20;
        if (interlaced) {
            failOption("cacheMegabytes", path + ": an interlaced PNG is decoded whole, " + std::to_string(megabytes) +
                                             " MB, more than a cache of " + std::to_string(cacheMegabytes) +
                                             " MB: give a cache of at least " + std::to_string(megabytes) +
                                             " MB, or save the image without interlacing");
        }
        reader->scratch_ = std::make_unique<ScratchFile>(path);
        d->scratchRow.resize(reader->rowBytes_);
        reader->decoder_ = std::thread([r = reader.get()] { r->decodeRows(); });
        return reader;
    }
    d->rows.resize(height);
    if (depth == 8) {
        reader->bytes_.reset(new uint8_t[samples]);
        for (size_t y = 0; y < height; ++y) {
            d->rows[y] = reader->bytes_.get() + y * rowSamples;
        }
    } else {
        reader->words_.reset(new uint16_t[samples]);
        for (size_t y = 0; y < height; ++y) {
            d->rows[y] = reinterpret_cast<png_bytep>(reader->words_.get() + y * rowSamples);
        }
    }
    if (interlaced) {
        // Every pass touches every row: nothing is final before the end.
        png_read_image(d->png, d->rows.data());
        png_read_end(d->png, nullptr);
        reader->rowsDecoded_ = static_cast<int>(height);
        reader->decoding_.reset();
        return reader;
    }
    reader->decoder_ = std::thread([r = reader.get()] { r->decodeRows(); });
    return reader;
}

void PngRasterReader::decodeRows() {
    Decoding* d = decoding_.get();
    const int height = info_.height;
    const auto publish = [&](int rows, const std::string& error) {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            rowsDecoded_.store(rows, std::memory_order_release);
            error_ = error;
        }
        progress_.notify_all();
    };
    if (setjmp(png_jmpbuf(d->png))) {
        publish(rowsDecoded_.load(std::memory_order_relaxed), path_ + ": " + damaged(d->error));
        return;
    }
    for (int y = 0; y < height && !stop_; ++y) {
        if (scratch_) {
            png_read_row(d->png, d->scratchRow.data(), nullptr);
            try {
                scratch_->write(static_cast<uint64_t>(y) * rowBytes_, d->scratchRow.data(), rowBytes_);
            } catch (const Error& e) {
                publish(rowsDecoded_.load(std::memory_order_relaxed), e.what());
                return;
            }
        } else {
            png_read_row(d->png, d->rows[static_cast<size_t>(y)], nullptr);
        }
        // The last rows are held back until the rest of the file is read and checked.
        if ((y + 1) % kRowsPerStep == 0 && y + 1 < height - kRowsPerStep) {
            publish(y + 1, "");
        }
    }
    if (stop_) {
        return;
    }
    png_read_end(d->png, nullptr);
    publish(height, "");
}

void PngRasterReader::waitForRows(int y1) const {
    if (rowsDecoded_.load(std::memory_order_acquire) >= y1) {
        return;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    progress_.wait(lock, [&] { return rowsDecoded_.load(std::memory_order_acquire) >= y1 || !error_.empty(); });
    if (rowsDecoded_.load(std::memory_order_acquire) < y1) {
        throw Error(error_);
    }
}

namespace {

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

// Columns [x0, x1) of row y, every channel, as T: in memory, or read from the scratch file
// into `buffer`.
template <typename T>
const T* PngRasterReader::rowSpan(int y, int x0, int x1, std::vector<uint8_t>& buffer) const {
    const size_t pixelBytes = static_cast<size_t>(info_.channels) * sizeof(T);
    const size_t offset = static_cast<size_t>(y) * rowBytes_ + static_cast<size_t>(x0) * pixelBytes;
    if (!scratch_) {
        const uint8_t* base = bytes_ ? bytes_.get() : reinterpret_cast<const uint8_t*>(words_.get());
        return reinterpret_cast<const T*>(base + offset);
    }
    buffer.resize(static_cast<size_t>(x1 - x0) * pixelBytes);
    scratch_->read(offset, buffer.data(), buffer.size());
    return reinterpret_cast<const T*>(buffer.data());
}

template <typename Out>
void PngRasterReader::copyWindow(int x0, int y0, int x1, int y1, int c0, int c1, Out* out) const {
    waitForRows(y1);
    thread_local std::vector<uint8_t> buffer;
    const size_t count = static_cast<size_t>(x1 - x0);
    for (int y = y0; y < y1; ++y) {
        out = info_.type == SampleType::UInt8
                  ? copyPixels(rowSpan<uint8_t>(y, x0, x1, buffer), count, info_.channels, c0, c1, out)
                  : copyPixels(rowSpan<uint16_t>(y, x0, x1, buffer), count, info_.channels, c0, c1, out);
    }
}

void PngRasterReader::readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const {
    copyWindow(x0, y0, x1, y1, channel, channel + 1, out);
}

void PngRasterReader::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const {
    copyWindow(x0, y0, x1, y1, c0, c1, out);
}

bool PngRasterReader::readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out,
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
