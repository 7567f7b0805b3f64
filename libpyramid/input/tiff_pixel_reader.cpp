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
                                                       int bytesPerSample, bool floatSamples) {
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

bool TiffPixelReader::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const {
    const size_t pixels = static_cast<size_t>(x1 - x0);
    const size_t pixelBytes = static_cast<size_t>(channels_) * static_cast<size_t>(bytesPerSample_);
    const uint64_t rowBytes = static_cast<uint64_t>(width_) * pixelBytes;
    const size_t wanted = static_cast<size_t>(c1 - c0);
    std::vector<uint8_t> row(pixels * pixelBytes);
    for (int y = y0; y < y1; ++y) {
        const auto r = static_cast<uint32_t>(y);
        const uint64_t offset = stripOffsets_[r / rowsPerStrip_] + (r % rowsPerStrip_) * rowBytes +
                                static_cast<uint64_t>(x0) * pixelBytes;
        if (!readFully(fd_, reinterpret_cast<char*>(row.data()), row.size(), offset)) {
            return false;
        }
        uint16_t* o = out + static_cast<size_t>(y - y0) * pixels * wanted;
        if (bytesPerSample_ == 1) {
            if (c0 == 0 && c1 == channels_) {
                std::copy(row.begin(), row.end(), o); // widened by value
                continue;
            }
            for (size_t i = 0; i < pixels; ++i) {
                for (size_t c = 0; c < wanted; ++c) {
                    o[i * wanted + c] = row[i * static_cast<size_t>(channels_) + static_cast<size_t>(c0) + c];
                }
            }
        } else {
            for (size_t i = 0; i < pixels; ++i) {
                for (size_t c = 0; c < wanted; ++c) {
                    std::memcpy(&o[i * wanted + c],
                                &row[(i * static_cast<size_t>(channels_) + static_cast<size_t>(c0) + c) * 2u], 2);
                }
            }
        }
    }
    return true;
}

bool TiffPixelReader::readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const {
    if (!float_) {
        return false;
    }
    const size_t pixels = static_cast<size_t>(x1 - x0);
    const size_t channels = static_cast<size_t>(channels_);
    const uint64_t rowBytes = static_cast<uint64_t>(width_) * channels * 4u;
    std::vector<float> row(channels == 1 ? 0 : pixels * channels);
    for (int y = y0; y < y1; ++y) {
        const auto r = static_cast<uint32_t>(y);
        const uint64_t offset = stripOffsets_[r / rowsPerStrip_] + (r % rowsPerStrip_) * rowBytes +
                                static_cast<uint64_t>(x0) * channels * 4u;
        float* o = out + static_cast<size_t>(y - y0) * pixels;
        // One band: straight into place.
        if (!readFully(fd_, reinterpret_cast<char*>(channels == 1 ? o : row.data()), pixels * channels * 4u, offset)) {
            return false;
        }
        if (channels > 1) {
            for (size_t i = 0; i < pixels; ++i) {
                o[i] = row[i * channels + static_cast<size_t>(channel)];
            }
        }
    }
    return true;
}

bool TiffPixelReader::readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out,
                                std::ptrdiff_t rowStride) const {
    if (bytesPerSample_ != 1) {
        return false;
    }
    const size_t pixels = static_cast<size_t>(x1 - x0);
    const size_t channels = static_cast<size_t>(channels_);
    const uint64_t rowBytes = static_cast<uint64_t>(width_) * channels;
    const size_t wanted = static_cast<size_t>(c1 - c0);
    const bool whole = c0 == 0 && c1 == channels_;
    std::vector<uint8_t> row(whole ? 0 : pixels * channels);
    for (int y = y0; y < y1; ++y) {
        const auto r = static_cast<uint32_t>(y);
        const uint64_t offset = stripOffsets_[r / rowsPerStrip_] + (r % rowsPerStrip_) * rowBytes +
                                static_cast<uint64_t>(x0) * channels;
        uint8_t* o = out + static_cast<std::ptrdiff_t>(y - y0) * rowStride;
        // All channels: straight into place, no intermediate copy.
        if (!readFully(fd_, reinterpret_cast<char*>(whole ? o : row.data()), pixels * channels, offset)) {
            return false;
        }
        if (!whole) {
            for (size_t i = 0; i < pixels; ++i) {
                std::copy_n(&row[i * channels + static_cast<size_t>(c0)], wanted, &o[i * wanted]);
            }
        }
    }
    return true;
}

} // namespace pyramid
