#include "libpyramid/input/tiff_strip_stream.hpp"

#include <tiffio.h>
#include <zlib.h>

#include <algorithm>
#include <vector>

#include "formats/error.hpp"
#include "formats/file_io.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"
#include "libpyramid/input/tiff_samples.hpp"

namespace pyramid {

namespace {

// Compressed bytes read from the file at a time.
constexpr size_t kChunkBytes = size_t{1} << 20;

struct Layout {
    uint32_t width = 0, height = 0, rowsPerStrip = 0;
    uint16_t channels = 1; // interleaved
    uint16_t bits = 0, format = 1, compression = COMPRESSION_NONE, predictor = PREDICTOR_NONE;
    bool swapped = false;
    size_t rowValues() const { return static_cast<size_t>(width) * channels; }
    size_t rowBytes() const { return rowValues() * (bits / 8); }
};

// Turns one row of stored bytes (the file's order, predictors applied) into its samples in the
// host's order: in place, or into `floats` (a row's bytes) for the floating-point predictor.
// Returns where the row is.
const uint8_t* finishRow(const Layout& l, uint8_t* bytes, uint8_t* floats) {
    if (l.predictor == PREDICTOR_FLOATINGPOINT) {
        undoFloatPredictor(bytes, l.width, floats);
        return floats;
    }
    if (l.swapped) {
        swapSampleBytes(bytes, l.rowValues(), l.bits);
    }
    if (l.predictor == PREDICTOR_HORIZONTAL) {
        undoHorizontalPredictor(bytes, l.width, l.bits, l.channels);
    }
    return bytes;
}

class StripReader {
public:
    StripReader(int fd, const std::string& path) : fd_(fd), path_(path) {}
    // Bytes [offset, offset + size) of the file, a chunk at a time: `consume(data, n)`.
    template <typename Consume>
    void read(uint64_t offset, uint64_t size, Consume consume) {
        chunk_.resize(static_cast<size_t>(std::min<uint64_t>(size, kChunkBytes)));
        while (size > 0) {
            const size_t n = static_cast<size_t>(std::min<uint64_t>(size, chunk_.size()));
            if (!readFully(fd_, chunk_.data(), n, offset)) {
                fail(path_, "read failed: a strip reaches past the end of the file");
            }
            consume(chunk_.data(), n);
            offset += n;
            size -= n;
        }
    }

private:
    int fd_;
    const std::string& path_;
    std::vector<uint8_t> chunk_;
};

} // namespace

void streamTiffRows(TIFF* tif, const std::string& path, const std::function<void(uint32_t, const uint8_t*)>& row) {
    Layout l;
    TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &l.width);
    TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &l.height);
    TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &l.rowsPerStrip);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &l.channels);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &l.bits);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &l.format);
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &l.compression);
    TIFFGetFieldDefaulted(tif, TIFFTAG_PREDICTOR, &l.predictor);
    l.swapped = TIFFIsByteSwapped(tif) != 0;
    l.rowsPerStrip = std::clamp<uint32_t>(l.rowsPerStrip, 1, l.height);
    std::vector<uint8_t> bytes(l.rowBytes());
    std::vector<uint8_t> floats; // rows with the floating-point predictor, undone
    if (l.predictor == PREDICTOR_FLOATINGPOINT) {
        floats.resize(l.rowBytes());
    }
    // The floating-point predictor of interleaved samples, and any predictor of 64-bit samples,
    // are left to libtiff.
    const bool streamed = (l.compression == COMPRESSION_NONE || l.compression == COMPRESSION_ADOBE_DEFLATE ||
                           l.compression == COMPRESSION_DEFLATE) &&
                          (l.predictor != PREDICTOR_FLOATINGPOINT || (l.channels == 1 && l.bits == 32)) &&
                          (l.bits != 64 || l.predictor == PREDICTOR_NONE);
    if (!streamed) {
        for (uint32_t s = 0; s < TIFFNumberOfStrips(tif); ++s) {
            if (!strileInFile(tif, s)) {
                fail(path, "damaged TIFF: strip " + std::to_string(s) + " lies beyond the end of the file");
            }
        }
        for (uint32_t y = 0; y < l.height; ++y) {
            // libtiff undoes the predictor and the byte order itself here.
            if (TIFFReadScanline(tif, bytes.data(), y, 0) < 0) {
                fail(path, "read failed: cannot decode row " + std::to_string(y));
            }
            row(y, bytes.data());
        }
        return;
    }
    StripReader reader(TIFFFileno(tif), path);
    const uint32_t strips = (l.height + l.rowsPerStrip - 1) / l.rowsPerStrip;
    z_stream z{};
    if (inflateInit(&z) != Z_OK) {
        fail(path, "cannot read: out of memory for a Deflate stream");
    }
    struct End {
        z_stream& z;
        ~End() { inflateEnd(&z); }
    } end{z};
    uint32_t y = 0;
    for (uint32_t s = 0; s < strips; ++s) {
        const uint32_t rows = std::min(l.rowsPerStrip, l.height - s * l.rowsPerStrip);
        const uint64_t offset = TIFFGetStrileOffset(tif, s);
        const uint64_t size = TIFFGetStrileByteCount(tif, s);
        size_t filled = 0; // bytes of the current row
        uint32_t done = 0; // rows of this strip
        const auto deliver = [&] {
            row(y++, finishRow(l, bytes.data(), floats.data()));
            filled = 0;
            ++done;
        };
        if (l.compression == COMPRESSION_NONE) {
            reader.read(offset, std::min<uint64_t>(size, static_cast<uint64_t>(l.rowBytes()) * rows),
                        [&](const uint8_t* data, size_t n) {
                            while (n > 0 && done < rows) {
                                const size_t take = std::min(n, bytes.size() - filled);
                                std::copy(data, data + take, bytes.data() + filled);
                                filled += take;
                                data += take;
                                n -= take;
                                if (filled == bytes.size()) {
                                    deliver();
                                }
                            }
                        });
        } else {
            inflateReset(&z);
            int status = Z_OK;
            reader.read(offset, size, [&](const uint8_t* data, size_t n) {
                z.next_in = const_cast<Bytef*>(data);
                z.avail_in = static_cast<uInt>(n);
                while (z.avail_in > 0 && status != Z_STREAM_END && done < rows) {
                    z.next_out = bytes.data() + filled;
                    z.avail_out = static_cast<uInt>(bytes.size() - filled);
                    status = inflate(&z, Z_NO_FLUSH);
                    if (status != Z_OK && status != Z_STREAM_END && status != Z_BUF_ERROR) {
                        fail(path, "read failed: damaged Deflate data in strip " + std::to_string(s));
                    }
                    filled = bytes.size() - z.avail_out;
                    if (filled == bytes.size()) {
                        deliver();
                    } else if (status == Z_BUF_ERROR) {
                        break; // needs the next chunk
                    }
                }
            });
        }
        if (done < rows) {
            fail(path, "read failed: strip " + std::to_string(s) + " holds " + std::to_string(done) + " of its " +
                           std::to_string(rows) + " rows");
        }
    }
}

} // namespace pyramid
