// A TIFF's internal transparency mask: the image of NewSubfileType 4 (a mask, not a reduced
// image) and of the first image's size that GDAL writes for a per-dataset mask (`-mask`,
// GDAL_TIFF_INTERNAL_MASK: common on JPEG-compressed orthophotos, whose lossy colours cannot
// keep a nodata value exact). Its samples are 1 bit (or 8) each; 0 marks a pixel without a
// value. Read block by block in bounded memory, from any number of threads, as the image is
// (tiff_block_reader.hpp): blocks are kept as decoded, eight pixels a byte.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "libpyramid/input/block_cache.hpp"

typedef struct tiff TIFF;

namespace pyramid {

// Directories looked through for a mask: the image's own, its overviews and their masks (a
// cloud-optimised file holds a mask and an overview for each level), never a long multi-page
// file's every page.
constexpr int kMaskDirectoriesSearched = 64;

// Whether `tif`'s current directory is the mask of an image of width x height.
bool isTiffMaskOf(TIFF* tif, uint32_t width, uint32_t height);

class TiffMaskReader {
public:
    // The mask of the file's first image (width x height), or null when it has none. Its blocks
    // take at most an eighth of the budget (but four blocks at least). Throws Error naming the
    // file for a mask libtiff cannot decode or whose blocks no image of its size has, and
    // OptionError("cacheMegabytes") for blocks beyond the budget.
    static std::unique_ptr<TiffMaskReader> open(const std::string& path, int width, int height, int cacheMegabytes);
    ~TiffMaskReader();
    TiffMaskReader(const TiffMaskReader&) = delete;
    TiffMaskReader& operator=(const TiffMaskReader&) = delete;

    // Columns [x0, x1) of rows [y0, y1): 0 where the mask has no value, else `on`, one value
    // every `step` elements of out (row-major, north first). Throws Error on a decoding error.
    // Thread-safe.
    void read(int x0, int y0, int x1, int y1, uint16_t on, uint16_t* out, size_t step) const;

private:
    TiffMaskReader() = default;
    TIFF* take() const;     // a handle on the mask's directory, idle or new
    void give(TIFF*) const; // back to the idle ones
    void decode(uint32_t index, BlockCache::Block& bytes) const;

    std::string path_;
    uint16_t directory_ = 0;
    uint32_t width_ = 0, height_ = 0;
    uint32_t blockWidth_ = 0, blockHeight_ = 0, blocksAcross_ = 0, blocks_ = 0;
    uint16_t bits_ = 1;
    size_t rowBytes_ = 0; // of a block's row, as decoded
    bool tiled_ = false;
    std::unique_ptr<BlockCache> cache_;
    mutable std::mutex mutex_;
    mutable std::vector<TIFF*> idle_;
};

} // namespace pyramid
