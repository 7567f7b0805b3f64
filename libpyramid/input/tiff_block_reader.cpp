#include "libpyramid/input/tiff_block_reader.hpp"

#include <tiffio.h>

#include <algorithm>
#include <cstring>
#include <type_traits>

#include "formats/error.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"
#include "libpyramid/input/tiff_samples.hpp"
#include "libpyramid/input/tiff_strip_stream.hpp"

namespace pyramid {

std::unique_ptr<TiffBlockReader> TiffBlockReader::open(const std::string& path, const RasterInfo& info, int cacheMegabytes) {
    if (info.formatName != "tiff" || info.channels < 1) {
        return nullptr;
    }
    std::unique_ptr<TiffBlockReader> b(new TiffBlockReader());
    b->path_ = path;
    TIFF* tif = b->openHandle();
    if (!tif) {
        return nullptr;
    }
    uint32_t width = 0, height = 0;
    uint16_t compression = 0, channels = 0, photometric = 0, planar = PLANARCONFIG_CONTIG;
    TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &width);
    TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &height);
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &compression);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &b->bits_);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &b->format_);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &channels);
    TIFFGetFieldDefaulted(tif, TIFFTAG_PHOTOMETRIC, &photometric);
    TIFFGetFieldDefaulted(tif, TIFFTAG_PLANARCONFIG, &planar);
    b->tiled_ = TIFFIsTiled(tif) != 0;
    if (b->tiled_) {
        TIFFGetField(tif, TIFFTAG_TILEWIDTH, &b->blockWidth_);
        TIFFGetField(tif, TIFFTAG_TILELENGTH, &b->blockHeight_);
    } else {
        b->blockWidth_ = width;
        TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &b->blockHeight_);
        b->blockHeight_ = std::min(b->blockHeight_, height);
    }
    b->width_ = width;
    b->height_ = height;
    // Codecs libtiff decodes to the stored sample type itself: the lossless ones, LERC (within
    // its stored largest error: elevation COGs) and WebP (8-bit RGB or RGBA, lossy or not:
    // imagery COGs), whose pixels libtiff gives as they are, as OpenImageIO reads them.
    const bool decoded = compression == COMPRESSION_NONE || compression == COMPRESSION_LZW ||
                         compression == COMPRESSION_ADOBE_DEFLATE || compression == COMPRESSION_DEFLATE ||
                         compression == COMPRESSION_PACKBITS || compression == COMPRESSION_ZSTD ||
                         compression == COMPRESSION_LZMA || compression == COMPRESSION_LERC ||
                         compression == COMPRESSION_WEBP;
    // JPEG (not the old-style JPEG of TIFF 6.0) of 8-bit samples: libjpeg decodes each block,
    // YCbCr ones converted to RGB by libjpeg itself (JPEGCOLORMODE), as OpenImageIO reads them.
    const bool jpeg = compression == COMPRESSION_JPEG && b->format_ == SAMPLEFORMAT_UINT && b->bits_ == 8;
    b->jpeg_ = jpeg;
    b->ycbcrJpeg_ = jpeg && photometric == PHOTOMETRIC_YCBCR && channels == 3;
    const bool integer = (b->format_ == SAMPLEFORMAT_INT || b->format_ == SAMPLEFORMAT_UINT) &&
                         (b->bits_ == 8 || b->bits_ == 16 || b->bits_ == 32);
    const bool real = b->format_ == SAMPLEFORMAT_IEEEFP && (b->bits_ == 32 || b->bits_ == 64);
    // One band of grey, or several: grey with extra samples, RGB, RGBA, interleaved or (not as
    // JPEG) in separate planes; JPEG's YCbCr; 8-bit palette indices, widened to RGB (other YCbCr
    // and palettes of other depths are left to the image I/O module).
    const bool palette = photometric == PHOTOMETRIC_PALETTE && channels == 1 && b->bits_ == 8 &&
                         b->format_ == SAMPLEFORMAT_UINT && !jpeg && info.channels == 3;
    b->planes_ = planar == PLANARCONFIG_SEPARATE ? channels : 1;
    const bool layout = (palette || (channels == static_cast<uint16_t>(info.channels) &&
                                     (photometric == PHOTOMETRIC_MINISBLACK ||
                                      (photometric == PHOTOMETRIC_RGB && channels >= 3) || b->ycbcrJpeg_))) &&
                        (b->planes_ == 1 || !jpeg);
    const bool ok = (decoded || jpeg) && (integer || real) && layout &&
                    width == static_cast<uint32_t>(info.width) && height == static_cast<uint32_t>(info.height) &&
                    b->blockWidth_ > 0 && b->blockHeight_ > 0 && TIFFIsCODECConfigured(compression);
    if (!ok) {
        TIFFClose(tif);
        return nullptr;
    }
    if (palette) {
        // OpenImageIO's reading of the 16-bit colour map: each value divided by 257, rounded down.
        uint16_t *red = nullptr, *green = nullptr, *blue = nullptr;
        if (TIFFGetField(tif, TIFFTAG_COLORMAP, &red, &green, &blue) != 1 || !red || !green || !blue) {
            TIFFClose(tif);
            fail(path, "damaged TIFF: palette indices without a colour map");
        }
        b->palette_.resize(3 * 256);
        for (size_t k = 0; k < 256; ++k) {
            b->palette_[3 * k] = static_cast<uint8_t>(red[k] / 257);
            b->palette_[3 * k + 1] = static_cast<uint8_t>(green[k] / 257);
            b->palette_[3 * k + 2] = static_cast<uint8_t>(blue[k] / 257);
        }
    }
    const uint32_t chunks = b->tiled_ ? TIFFNumberOfTiles(tif) : TIFFNumberOfStrips(tif);
    b->chunksPerPlane_ = chunks / b->planes_;
    uint16_t predictor = PREDICTOR_NONE;
    TIFFGetFieldDefaulted(tif, TIFFTAG_PREDICTOR, &predictor);
    b->floatPredictorDeflate_ = real && b->bits_ == 32 && channels == 1 && predictor == PREDICTOR_FLOATINGPOINT &&
                                (compression == COMPRESSION_ADOBE_DEFLATE || compression == COMPRESSION_DEFLATE);
    // A tile may reach past the image (to a multiple of 16, or a writer's usual size such as
    // 512 for a small image), never far beyond: anything larger is a damaged or hostile
    // declaration, and is refused before a block is allocated.
    const auto plausible = [](uint32_t block, uint32_t image) {
        return block <= std::max<uint32_t>(image + 15, 4096);
    };
    if (!plausible(b->blockWidth_, width) || !plausible(b->blockHeight_, height)) {
        TIFFClose(tif);
        fail(path, "damaged TIFF: " + std::string(b->tiled_ ? "tiles" : "strips") + " of " +
                       std::to_string(b->blockWidth_) + " x " + std::to_string(b->blockHeight_) + " samples for a " +
                       std::to_string(width) + " x " + std::to_string(height) + " image");
    }
    b->blocksAcross_ = (width + b->blockWidth_ - 1) / b->blockWidth_;
    const size_t budget = static_cast<size_t>(std::max(cacheMegabytes, 1)) << 20;
    b->channels_ = palette ? 3 : channels;
    const size_t blockBytes = static_cast<size_t>(b->blockWidth_) * b->blockHeight_ * b->pixelBytes();
    const uint32_t blocksDown = (height + b->blockHeight_ - 1) / b->blockHeight_;
    // Blocks up to a quarter of the budget: the cache keeps at least four, which the reads of
    // a window across block boundaries need.
    if (blockBytes <= budget / 4) {
        b->cache_ = std::make_unique<BlockCache>(budget, blockBytes);
    } else if (!b->tiled_ && (b->planes_ > 1 || palette)) {
        TIFFClose(tif); // huge strips of planes or indices: read by the image I/O module
        return nullptr;
    } else if (b->tiled_) {
        TIFFClose(tif);
        failBlocksBeyondCache(path,
                              "tiles of " + std::to_string(b->blockWidth_) + " x " + std::to_string(b->blockHeight_) +
                                  " samples",
                              blockBytes, cacheMegabytes);
    }
    if (b->planes_ > 1 && (b->chunksPerPlane_ != b->blocksAcross_ * blocksDown || chunks % b->planes_ != 0)) {
        TIFFClose(tif);
        fail(path, "damaged TIFF: " + std::to_string(chunks) + (b->tiled_ ? " tiles" : " strips") + " for " +
                       std::to_string(b->planes_) + " planes of " + std::to_string(b->blocksAcross_ * blocksDown) +
                       " blocks");
    }
    if (b->jpeg_) {
        TIFFClose(tif); // opened again as every JPEG handle is (openHandle)
        if (!(tif = b->openHandle())) {
            return nullptr;
        }
    }
    b->idle_.push_back(tif);
    return b;
}

TiffBlockReader::~TiffBlockReader() {
    for (TIFF* tif : idle_) {
        TIFFClose(tif);
    }
}

namespace {

// Decoded samples (the file's own type, host order) as T: float32 by value, 16-bit values (8 or
// 16-bit unsigned samples), or bytes as they are (8-bit samples).
template <typename T>
void convertSamples(const uint8_t* raw, size_t count, int bits, int format, T* out) {
    if constexpr (std::is_same_v<T, float>) {
        samplesToFloat(raw, count, bits, format, out);
    } else if constexpr (std::is_same_v<T, uint16_t>) {
        samplesToUInt16(raw, count, bits, out);
    } else {
        static_assert(std::is_same_v<T, uint8_t>);
        std::memcpy(out, raw, count);
    }
}

} // namespace

void TiffBlockReader::read(int x0, int y0, int x1, int y1, int c0, int c1, float* out) {
    readAs(x0, y0, x1, y1, c0, c1, out, static_cast<std::ptrdiff_t>(x1 - x0) * (c1 - c0));
}

void TiffBlockReader::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) {
    if (format_ != SAMPLEFORMAT_UINT || (bits_ != 8 && bits_ != 16)) {
        fail(path_, "16-bit read of samples that are not 8 or 16-bit unsigned");
    }
    readAs(x0, y0, x1, y1, c0, c1, out, static_cast<std::ptrdiff_t>(x1 - x0) * (c1 - c0));
}

void TiffBlockReader::readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out,
                                std::ptrdiff_t rowStride) {
    if (format_ != SAMPLEFORMAT_UINT || bits_ != 8) {
        fail(path_, "8-bit read of samples that are not 8-bit unsigned");
    }
    readAs(x0, y0, x1, y1, c0, c1, out, rowStride);
}

template <typename T>
void TiffBlockReader::convertPixels(const uint8_t* from, size_t pixels, size_t c0, size_t wanted, T* to) const {
    if (wanted == channels_) {
        convertSamples(from, pixels * wanted, bits_, format_, to);
        return;
    }
    const size_t sampleBytes = bits_ / 8u;
    for (size_t i = 0; i < pixels; ++i) {
        convertSamples(from + i * pixelBytes() + c0 * sampleBytes, wanted, bits_, format_, to + i * wanted);
    }
}

template <typename T>
void TiffBlockReader::readAs(int x0, int y0, int x1, int y1, int c0, int c1, T* out, std::ptrdiff_t rowStride) {
    if (cache_) {
        readBlocks(x0, y0, x1, y1, c0, c1, out, rowStride);
        return;
    }
    // Strips beyond the cache: the whole image decoded once, at the first read, into the
    // scratch file (opening stays cheap, and a caller that only describes the file pays nothing).
    std::call_once(spilled_, [this] {
        TIFF* tif = openHandle();
        if (!tif) {
            fail(path_, "cannot reopen the file");
        }
        struct Close {
            TIFF* tif;
            ~Close() { TIFFClose(tif); }
        } close{tif};
        auto rows = std::make_unique<ScratchFile>(path_);
        const size_t rowBytes = static_cast<size_t>(width_) * pixelBytes();
        if (jpeg_) {
            takeJpegWarning();
        }
        streamTiffRows(tif, path_, [&](uint32_t y, const uint8_t* bytes) {
            rows->write(static_cast<uint64_t>(y) * rowBytes, bytes, rowBytes);
        });
        failOnJpegWarning("its strips");
        rows_ = std::move(rows);
    });
    const size_t outWidth = static_cast<size_t>(x1 - x0);
    thread_local std::vector<uint8_t> row;
    row.resize(outWidth * pixelBytes());
    for (int y = y0; y < y1; ++y) {
        rows_->read((static_cast<uint64_t>(y) * width_ + static_cast<uint64_t>(x0)) * pixelBytes(), row.data(),
                    row.size());
        convertPixels(row.data(), outWidth, static_cast<size_t>(c0), static_cast<size_t>(c1 - c0),
                      out + static_cast<std::ptrdiff_t>(y - y0) * rowStride);
    }
}

template <typename T>
void TiffBlockReader::readBlocks(int x0, int y0, int x1, int y1, int c0, int c1, T* out, std::ptrdiff_t rowStride) {
    const size_t wanted = static_cast<size_t>(c1 - c0);
    const auto decodeWith = [this](uint32_t index) {
        return [this, index](std::vector<uint8_t>& bytes) {
            TIFF* tif = nullptr;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                if (!idle_.empty()) {
                    tif = idle_.back();
                    idle_.pop_back();
                }
            }
            if (!tif && !(tif = openHandle())) {
                fail(path_, "cannot reopen the file");
            }
            struct Return {
                TiffBlockReader& r;
                TIFF* tif;
                ~Return() {
                    std::lock_guard<std::mutex> lock(r.mutex_);
                    r.idle_.push_back(tif);
                }
            } back{*this, tif};
            decode(tif, index, bytes);
        };
    };
    for (uint32_t by = static_cast<uint32_t>(y0) / blockHeight_; by * blockHeight_ < static_cast<uint32_t>(y1); ++by) {
        for (uint32_t bx = static_cast<uint32_t>(x0) / blockWidth_; bx * blockWidth_ < static_cast<uint32_t>(x1);
             ++bx) {
            const uint32_t index = by * blocksAcross_ + bx;
            const std::shared_ptr<const BlockCache::Block> block = cache_->get(index, decodeWith(index));
            const int bx0 = static_cast<int>(bx * blockWidth_), by0 = static_cast<int>(by * blockHeight_);
            const int cx0 = std::max(x0, bx0), cx1 = std::min(x1, bx0 + static_cast<int>(blockWidth_));
            const int cy0 = std::max(y0, by0), cy1 = std::min(y1, by0 + static_cast<int>(blockHeight_));
            for (int y = cy0; y < cy1; ++y) {
                const size_t pixel = static_cast<size_t>(y - by0) * blockWidth_ + static_cast<size_t>(cx0 - bx0);
                const uint8_t* from = block->data() + pixel * pixelBytes();
                T* to = out + static_cast<std::ptrdiff_t>(y - y0) * rowStride +
                        static_cast<std::ptrdiff_t>(static_cast<size_t>(cx0 - x0) * wanted);
                convertPixels(from, static_cast<size_t>(cx1 - cx0), static_cast<size_t>(c0), wanted, to);
            }
        }
    }
}

// Without memory mapping ("m"): libtiff would otherwise read compressed blocks through a map
// of the whole file, whose touched pages count against the process's memory as they stay
// resident; read() copies each block into a buffer of its size instead.
TIFF* TiffBlockReader::openHandle() const {
    TIFF* tif = openTiffQuietly(path_, "rm", jpeg_);
    if (tif && ycbcrJpeg_) {
        TIFFSetField(tif, TIFFTAG_JPEGCOLORMODE, JPEGCOLORMODE_RGB); // every handle decodes to RGB
    }
    return tif;
}

} // namespace pyramid
