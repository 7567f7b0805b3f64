#include "libpyramid/input/tiff_mask_reader.hpp"

#include <tiffio.h>

#include <algorithm>

#include "formats/error.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"

namespace pyramid {

bool isTiffMaskOf(TIFF* tif, uint32_t width, uint32_t height) {
    uint32_t kind = 0, w = 0, h = 0;
    uint16_t bits = 0, channels = 0, format = 0;
    TIFFGetFieldDefaulted(tif, TIFFTAG_SUBFILETYPE, &kind);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &channels);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &format);
    return (kind & (FILETYPE_MASK | FILETYPE_REDUCEDIMAGE)) == FILETYPE_MASK &&
           TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w) == 1 && TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &h) == 1 &&
           w == width && h == height && channels == 1 && (bits == 1 || bits == 8) && format == SAMPLEFORMAT_UINT;
}

std::unique_ptr<TiffMaskReader> TiffMaskReader::open(const std::string& path, int width, int height,
                                                     int cacheMegabytes) {
    TIFF* tif = openTiffQuietly(path, "rm");
    if (!tif) {
        return nullptr;
    }
    std::unique_ptr<TiffMaskReader> m(new TiffMaskReader());
    m->path_ = path;
    m->width_ = static_cast<uint32_t>(width);
    m->height_ = static_cast<uint32_t>(height);
    bool found = false;
    for (int d = 1; d < kMaskDirectoriesSearched && !found && TIFFReadDirectory(tif) == 1; ++d) {
        found = isTiffMaskOf(tif, m->width_, m->height_);
        m->directory_ = static_cast<uint16_t>(d);
    }
    if (!found) {
        TIFFClose(tif);
        return nullptr;
    }
    uint16_t compression = 0;
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &compression);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &m->bits_);
    m->tiled_ = TIFFIsTiled(tif) != 0;
    if (m->tiled_) {
        TIFFGetField(tif, TIFFTAG_TILEWIDTH, &m->blockWidth_);
        TIFFGetField(tif, TIFFTAG_TILELENGTH, &m->blockHeight_);
        m->blocks_ = TIFFNumberOfTiles(tif);
    } else {
        m->blockWidth_ = m->width_;
        TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &m->blockHeight_);
        m->blockHeight_ = std::min(m->blockHeight_, m->height_);
        m->blocks_ = TIFFNumberOfStrips(tif);
    }
    if (!TIFFIsCODECConfigured(compression)) {
        TIFFClose(tif);
        fail(path, "its transparency mask is compressed as libtiff here cannot decode (compression " +
                       std::to_string(compression) + ")");
    }
    const auto plausible = [](uint32_t block, uint32_t image) {
        return block > 0 && block <= std::max<uint32_t>(image + 15, 4096);
    };
    m->blocksAcross_ = plausible(m->blockWidth_, m->width_) ? (m->width_ + m->blockWidth_ - 1) / m->blockWidth_ : 0;
    const uint32_t blocksDown =
        plausible(m->blockHeight_, m->height_) ? (m->height_ + m->blockHeight_ - 1) / m->blockHeight_ : 0;
    if (m->blocksAcross_ == 0 || blocksDown == 0 || m->blocks_ != m->blocksAcross_ * blocksDown) {
        TIFFClose(tif);
        fail(path, "damaged TIFF: a transparency mask of " + std::to_string(m->blocks_) + " blocks of " +
                       std::to_string(m->blockWidth_) + " x " + std::to_string(m->blockHeight_) + " for a " +
                       std::to_string(width) + " x " + std::to_string(height) + " image");
    }
    m->rowBytes_ = (static_cast<size_t>(m->blockWidth_) * m->bits_ + 7) / 8;
    const size_t blockBytes = m->rowBytes_ * m->blockHeight_;
    const size_t budget = std::max<size_t>((static_cast<size_t>(std::max(cacheMegabytes, 1)) << 20) / 8, 4 * blockBytes);
    if (blockBytes > (static_cast<size_t>(std::max(cacheMegabytes, 1)) << 20) / 4) {
        TIFFClose(tif);
        failBlocksBeyondCache(path,
                              "transparency mask blocks of " + std::to_string(m->blockWidth_) + " x " +
                                  std::to_string(m->blockHeight_) + " samples",
                              blockBytes, cacheMegabytes);
    }
    m->cache_ = std::make_unique<BlockCache>(budget, blockBytes);
    m->idle_.push_back(tif);
    return m;
}

TiffMaskReader::~TiffMaskReader() {
    for (TIFF* tif : idle_) {
        TIFFClose(tif);
    }
}

TIFF* TiffMaskReader::take() const {
    {
        const std::lock_guard lock(mutex_);
        if (!idle_.empty()) {
            TIFF* tif = idle_.back();
            idle_.pop_back();
            return tif;
        }
    }
    TIFF* tif = openTiffQuietly(path_, "rm");
    if (!tif || TIFFSetDirectory(tif, directory_) != 1 || !isTiffMaskOf(tif, width_, height_)) {
        if (tif) {
            TIFFClose(tif);
        }
        fail(path_, "cannot reopen its transparency mask");
    }
    return tif;
}

void TiffMaskReader::give(TIFF* tif) const {
    const std::lock_guard lock(mutex_);
    idle_.push_back(tif);
}

void TiffMaskReader::decode(uint32_t index, BlockCache::Block& bytes) const {
    TIFF* tif = take();
    struct Give {
        const TiffMaskReader& m;
        TIFF* tif;
        ~Give() { m.give(tif); }
    } back{*this, tif};
    // The last strip may hold fewer rows: the rest of the buffer is no pixel's.
    std::fill(bytes.begin(), bytes.end(), uint8_t{0});
    const auto size = static_cast<tmsize_t>(bytes.size());
    const tmsize_t got = !strileInFile(tif, index) ? -1
                         : tiled_                  ? TIFFReadEncodedTile(tif, index, bytes.data(), size)
                                                   : TIFFReadEncodedStrip(tif, index, bytes.data(), size);
    if (got < 0) {
        fail(path_, std::string("cannot decode its transparency mask's ") + (tiled_ ? "tile " : "strip ") +
                        std::to_string(index));
    }
}

void TiffMaskReader::read(int x0, int y0, int x1, int y1, uint16_t on, uint16_t* out, size_t step) const {
    const size_t width = static_cast<size_t>(x1 - x0);
    for (uint32_t by = static_cast<uint32_t>(y0) / blockHeight_; by * blockHeight_ < static_cast<uint32_t>(y1); ++by) {
        for (uint32_t bx = static_cast<uint32_t>(x0) / blockWidth_; bx * blockWidth_ < static_cast<uint32_t>(x1); ++bx) {
            const uint32_t index = by * blocksAcross_ + bx;
            const auto block = cache_->get(index, [&](BlockCache::Block& b) { decode(index, b); });
            const uint32_t ya = std::max(by * blockHeight_, static_cast<uint32_t>(y0));
            const uint32_t yb = std::min((by + 1) * blockHeight_, static_cast<uint32_t>(y1));
            const uint32_t xa = std::max(bx * blockWidth_, static_cast<uint32_t>(x0));
            const uint32_t xb = std::min((bx + 1) * blockWidth_, static_cast<uint32_t>(x1));
            for (uint32_t y = ya; y < yb; ++y) {
                const uint8_t* row = block->data() + (y - by * blockHeight_) * rowBytes_;
                uint16_t* to = out + ((y - static_cast<uint32_t>(y0)) * width + (xa - static_cast<uint32_t>(x0))) * step;
                for (uint32_t x = xa - bx * blockWidth_; x < xb - bx * blockWidth_; ++x, to += step) {
                    const bool value = bits_ == 1 ? ((row[x >> 3] >> (7 - (x & 7))) & 1) != 0 : row[x] != 0;
                    *to = value ? on : uint16_t{0};
                }
            }
        }
    }
}

} // namespace pyramid
