#include "libpyramid/input/tiff_pixel_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <tiffio.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

#include "formats/file_io.hpp"

namespace pyramid {

namespace {

int ignoreTiffMessage(TIFF*, void*, const char*, const char*, va_list) { return 1; }

// The first libjpeg warning of this thread's decoding (libtiff names libjpeg "JPEGLib").
thread_local std::string jpegWarning;

int noteJpegWarning(TIFF*, void*, const char* module, const char* format, va_list arguments) {
    if (module && std::strcmp(module, "JPEGLib") == 0 && jpegWarning.empty()) {
        char text[256];
        std::vsnprintf(text, sizeof text, format, arguments);
        jpegWarning = text;
        jpegWarning.erase(jpegWarning.find_last_not_of(" .\n") + 1);
    }
    return 1;
}

} // namespace

namespace {

// The size of the file behind `tif` (0 when fstat fails: then every block lies beyond it).
uint64_t fileBytesOf(TIFF* tif) {
    struct stat st {};
    return ::fstat(TIFFFileno(tif), &st) == 0 && st.st_size > 0 ? static_cast<uint64_t>(st.st_size) : 0;
}

bool strileWithin(TIFF* tif, uint32_t index, uint64_t fileBytes) {
    const uint64_t offset = TIFFGetStrileOffset(tif, index), bytes = TIFFGetStrileByteCount(tif, index);
    return offset <= fileBytes && bytes <= fileBytes - offset;
}

} // namespace

bool strileInFile(TIFF* tif, uint32_t index) { return strileWithin(tif, index, fileBytesOf(tif)); }

std::string tiffBlockBeyondTheFile(const std::string& path) {
    TIFF* tif = openTiffQuietly(path, "rm");
    if (!tif) {
        return "";
    }
    const bool tiled = TIFFIsTiled(tif) != 0;
    const uint32_t blocks = tiled ? TIFFNumberOfTiles(tif) : TIFFNumberOfStrips(tif);
    const uint64_t fileBytes = fileBytesOf(tif);
    std::string problem;
    for (uint32_t i = 0; i < blocks && problem.empty(); ++i) {
        if (!strileWithin(tif, i, fileBytes)) {
            problem = std::string("damaged TIFF: ") + (tiled ? "tile " : "strip ") + std::to_string(i) +
                      " lies beyond the end of the file";
        }
    }
    TIFFClose(tif);
    return problem;
}

TIFF* openTiffQuietly(const std::string& path, const char* mode, bool noteJpegWarnings) {
    TIFFOpenOptions* options = TIFFOpenOptionsAlloc();
    TIFFOpenOptionsSetErrorHandlerExtR(options, ignoreTiffMessage, nullptr);
    TIFFOpenOptionsSetWarningHandlerExtR(options, noteJpegWarnings ? noteJpegWarning : ignoreTiffMessage, nullptr);
    TIFF* tif = TIFFOpenExt(path.c_str(), mode, options);
    TIFFOpenOptionsFree(options);
    return tif;
}

std::string takeJpegWarning() { return std::exchange(jpegWarning, std::string()); }

std::unique_ptr<TiffPixelReader> TiffPixelReader::open(const std::string& path, int width, int height, int channels,
                                                       int bytesPerSample, bool floatSamples, size_t cacheBytes) {
    // Multi-byte samples are read as stored: only in the host's byte order.
    const bool supported = floatSamples ? bytesPerSample == 4 : (bytesPerSample == 1 || bytesPerSample == 2);
    if (!supported || (bytesPerSample > 1 && std::endian::native != std::endian::little)) {
        return nullptr;
    }
    TIFF* tif = openTiffQuietly(path, "rm");
    if (!tif) {
        return nullptr;
    }
    uint32_t w = 0, h = 0, rowsPerStrip = 0;
    uint16_t compression = 0, bits = 0, format = 0, samples = 0, planar = 0;
    TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w);
    TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &h);
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &compression);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &format);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &samples);
    TIFFGetFieldDefaulted(tif, TIFFTAG_PLANARCONFIG, &planar);
    TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &rowsPerStrip);
    rowsPerStrip = std::min(rowsPerStrip, h);
    const uint64_t rowBytes = static_cast<uint64_t>(w) * samples * static_cast<uint64_t>(bytesPerSample);
    std::unique_ptr<TiffPixelReader> reader;
    // Palette, YCbCr or other photometric interpretations are converted by the cache; only
    // samples stored as they are returned qualify.
    uint16_t photometric = 0;
    TIFFGetFieldDefaulted(tif, TIFFTAG_PHOTOMETRIC, &photometric);
    const bool plainSamples = photometric == PHOTOMETRIC_MINISBLACK || photometric == PHOTOMETRIC_RGB;
    if (!TIFFIsTiled(tif) && !TIFFIsByteSwapped(tif) && compression == COMPRESSION_NONE && plainSamples &&
        bits == 8 * bytesPerSample &&
        format == (floatSamples ? SAMPLEFORMAT_IEEEFP : SAMPLEFORMAT_UINT) && samples == channels &&
        (planar == PLANARCONFIG_CONTIG || samples == 1) && w == static_cast<uint32_t>(width) &&
        h == static_cast<uint32_t>(height) && rowsPerStrip > 0 &&
        TIFFNumberOfStrips(tif) == (h + rowsPerStrip - 1) / rowsPerStrip) {
        reader.reset(new TiffPixelReader());
        reader->width_ = width;
        reader->channels_ = channels;
        reader->bytesPerSample_ = bytesPerSample;
        reader->float_ = floatSamples;
        reader->rowsPerStrip_ = rowsPerStrip;
        reader->height_ = height;
        reader->pixelBytes_ = static_cast<size_t>(channels) * static_cast<size_t>(bytesPerSample);
        reader->rowBytes_ = rowBytes;
        reader->cacheBytes_ = std::min(kCacheBytes, cacheBytes);
        const uint32_t strips = TIFFNumberOfStrips(tif);
        for (uint32_t s = 0; s < strips && reader; ++s) {
            const uint32_t rows = std::min(rowsPerStrip, h - s * rowsPerStrip);
            const uint64_t offset = TIFFGetStrileOffset(tif, s);
            // A strip must hold all its rows, or the cache reads (and reports) the file.
            if (offset == 0 || TIFFGetStrileByteCount(tif, s) < rows * rowBytes) {
                reader.reset();
            } else {
                reader->stripOffsets_.push_back(offset);
            }
        }
    }
    TIFFClose(tif);
    if (reader) {
        reader->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (reader->fd_ < 0) {
            reader.reset();
        }
    }
    return reader;
}

TiffPixelReader::~TiffPixelReader() {
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

uint64_t TiffPixelReader::rowOffset(int y) const {
    const auto r = static_cast<uint32_t>(y);
    return stripOffsets_[r / rowsPerStrip_] + (r % rowsPerStrip_) * rowBytes_;
}

void TiffPixelReader::shapeBlocks(int windowRows) const {
    // The blocks under a window of whole rows (the windows of a row of footprints share them):
    const auto rowBands = static_cast<size_t>(windowRows / kBlockRows + 2);
    const bool wholeRows = 2 * rowBands * kBlockRows * rowBytes_ <= cacheBytes_;
    blockColumns_ = wholeRows ? width_ : std::max(1, static_cast<int>(kChunkBytes / pixelBytes_));
    blocksAcross_ = (width_ + blockColumns_ - 1) / blockColumns_;
    blockBytes_ = static_cast<size_t>(kBlockRows) * static_cast<size_t>(blockColumns_) * pixelBytes_;
}

bool TiffPixelReader::throughBlocks(int x0, int y0, int x1, int y1) const {
    if (x1 <= x0 || static_cast<uint64_t>(x1 - x0) * pixelBytes_ > kNarrowRowBytes || y1 - y0 < kBlockRows) {
        return false;
    }
    std::call_once(shaped_, [&] { shapeBlocks(y1 - y0); });
    const auto blocks = static_cast<size_t>((y1 - 1) / kBlockRows - y0 / kBlockRows + 1) *
                        static_cast<size_t>((x1 - 1) / blockColumns_ - x0 / blockColumns_ + 1);
    return 2 * blocks * blockBytes_ <= cacheBytes_;
}

std::shared_ptr<TiffPixelReader::Block> TiffPixelReader::block(int by, int bx) const {
    const uint64_t key = static_cast<uint64_t>(by) * static_cast<uint64_t>(blocksAcross_) + static_cast<uint64_t>(bx);
    std::lock_guard lock(cacheMutex_);
    if (const auto found = cache_.find(key); found != cache_.end()) {
        recent_.splice(recent_.begin(), recent_, found->second.second);
        return found->second.first;
    }
    auto made = std::make_shared<Block>();
    if (spare_.empty()) {
        made->bytes.reset(new uint8_t[blockBytes_]); // not cleared: every byte is read into
    } else {
        made->bytes = std::move(spare_.back());
        spare_.pop_back();
    }
    recent_.push_front(key);
    cache_.emplace(key, std::make_pair(made, recent_.begin()));
    cachedBytes_ += blockBytes_;
    // The least recently used go; a reader still copying from one keeps it until it is done.
    while (cachedBytes_ > cacheBytes_ && recent_.size() > 1) {
        const auto gone = cache_.find(recent_.back());
        if (gone->second.first.use_count() == 1) {
            spare_.push_back(std::move(gone->second.first->bytes));
        }
        cache_.erase(gone);
        recent_.pop_back();
        cachedBytes_ -= blockBytes_;
    }
    return made;
}

void TiffPixelReader::load(Block& b, int by, int bx) const {
    const int r0 = by * kBlockRows, r1 = std::min(height_, r0 + kBlockRows);
    const int c0 = bx * blockColumns_, c1 = std::min(width_, c0 + blockColumns_);
    const size_t pieceBytes = static_cast<size_t>(c1 - c0) * pixelBytes_;
    b.stride = pieceBytes;
    for (int y = r0; y < r1;) {
        // Whole rows that follow each other in the file are read in one call.
        int last = y + 1;
        if (c1 - c0 == width_) {
            while (last < r1 && rowOffset(last) == rowOffset(last - 1) + rowBytes_) {
                ++last;
            }
        }
        const uint64_t offset = rowOffset(y) + static_cast<uint64_t>(c0) * pixelBytes_;
        if (!readFully(fd_, b.bytes.get() + static_cast<size_t>(y - r0) * pieceBytes,
                       static_cast<size_t>(last - y) * pieceBytes, offset)) {
            b.error = errno;
            return;
        }
        y = last;
    }
    b.ok = true;
}

bool TiffPixelReader::forEachPiece(int x0, int y0, int x1, int y1,
                                   const std::function<void(int, int, const uint8_t*, size_t)>& take) const {
    for (int by = y0 / kBlockRows; by <= (y1 - 1) / kBlockRows; ++by) {
        for (int bx = x0 / blockColumns_; bx <= (x1 - 1) / blockColumns_; ++bx) {
            const std::shared_ptr<Block> b = block(by, bx);
            std::call_once(b->once, [&] { load(*b, by, bx); });
            if (!b->ok) {
                errno = b->error;
                return false;
            }
            const int c0 = bx * blockColumns_;
            const int xs = std::max(x0, c0), xe = std::min(x1, c0 + blockColumns_);
            const int ys = std::max(y0, by * kBlockRows), ye = std::min(y1, (by + 1) * kBlockRows);
            for (int y = ys; y < ye; ++y) {
                take(y, xs,
                     b->bytes.get() + static_cast<size_t>(y - by * kBlockRows) * b->stride +
                         static_cast<size_t>(xs - c0) * pixelBytes_,
                     static_cast<size_t>(xe - xs));
            }
        }
    }
    return true;
}

bool TiffPixelReader::forEachRow(int x0, int y0, int x1, int y1,
                                 const std::function<void(int, int, const uint8_t*, size_t)>& take) const {
    if (throughBlocks(x0, y0, x1, y1)) {
        return forEachPiece(x0, y0, x1, y1, take);
    }
    const size_t pixels = static_cast<size_t>(x1 - x0);
    std::vector<uint8_t> row(pixels * pixelBytes_);
    for (int y = y0; y < y1; ++y) {
        if (!readFully(fd_, row.data(), row.size(), rowOffset(y) + static_cast<uint64_t>(x0) * pixelBytes_)) {
            return false;
        }
        take(y, x0, row.data(), pixels);
    }
    return true;
}

bool TiffPixelReader::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const {
    const size_t pixels = static_cast<size_t>(x1 - x0);
    const size_t channels = static_cast<size_t>(channels_);
    const size_t wanted = static_cast<size_t>(c1 - c0);
    return forEachRow(x0, y0, x1, y1, [&](int y, int x, const uint8_t* row, size_t n) {
        uint16_t* o = out + (static_cast<size_t>(y - y0) * pixels + static_cast<size_t>(x - x0)) * wanted;
        if (bytesPerSample_ == 1) {
            if (wanted == channels) {
                std::copy_n(row, n * channels, o); // widened by value
                return;
            }
            for (size_t i = 0; i < n; ++i) {
                for (size_t c = 0; c < wanted; ++c) {
                    o[i * wanted + c] = row[i * channels + static_cast<size_t>(c0) + c];
                }
            }
        } else {
            for (size_t i = 0; i < n; ++i) {
                for (size_t c = 0; c < wanted; ++c) {
                    std::memcpy(&o[i * wanted + c], &row[(i * channels + static_cast<size_t>(c0) + c) * 2u], 2);
                }
            }
        }
    });
}

bool TiffPixelReader::readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const {
    if (!float_) {
        return false;
    }
    const size_t pixels = static_cast<size_t>(x1 - x0);
    const size_t channels = static_cast<size_t>(channels_);
    if (channels == 1 && !throughBlocks(x0, y0, x1, y1)) {
        // One band of a wide window: each row straight into place.
        for (int y = y0; y < y1; ++y) {
            if (!readFully(fd_, out + static_cast<size_t>(y - y0) * pixels, pixels * 4u,
                           rowOffset(y) + static_cast<uint64_t>(x0) * 4u)) {
                return false;
            }
        }
        return true;
    }
    return forEachRow(x0, y0, x1, y1, [&](int y, int x, const uint8_t* row, size_t n) {
        float* o = out + static_cast<size_t>(y - y0) * pixels + static_cast<size_t>(x - x0);
        for (size_t i = 0; i < n; ++i) {
            std::memcpy(&o[i], row + (i * channels + static_cast<size_t>(channel)) * 4u, 4);
        }
    });
}

bool TiffPixelReader::readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out,
                                std::ptrdiff_t rowStride) const {
    if (bytesPerSample_ != 1) {
        return false;
    }
    const size_t channels = static_cast<size_t>(channels_);
    const size_t wanted = static_cast<size_t>(c1 - c0);
    const bool whole = wanted == channels;
    if (whole && !throughBlocks(x0, y0, x1, y1)) {
        // All channels of wide windows: each row straight into place, no intermediate copy.
        const size_t bytes = static_cast<size_t>(x1 - x0) * channels;
        for (int y = y0; y < y1; ++y) {
            if (!readFully(fd_, reinterpret_cast<char*>(out + static_cast<std::ptrdiff_t>(y - y0) * rowStride), bytes,
                           rowOffset(y) + static_cast<uint64_t>(x0) * channels)) {
                return false;
            }
        }
        return true;
    }
    return forEachRow(x0, y0, x1, y1, [&](int y, int x, const uint8_t* row, size_t n) {
        uint8_t* o = out + static_cast<std::ptrdiff_t>(y - y0) * rowStride + static_cast<std::ptrdiff_t>(x - x0) *
                                                                                static_cast<std::ptrdiff_t>(wanted);
        if (whole) {
            std::copy_n(row, n * channels, o);
            return;
        }
        for (size_t i = 0; i < n; ++i) {
            std::copy_n(&row[i * channels + static_cast<size_t>(c0)], wanted, &o[i * wanted]);
        }
    });
}

} // namespace pyramid
