// The readers behind a RasterSource (raster_source.hpp): for a file, the direct readers that know
// it (a TIFF's rows or blocks, a raw grid's rows, a PNG, JPEG or ASCII grid file decoded whole) or else
// the image I/O module (image_io_module.hpp); for a mosaic, its files; or pixels a caller
// computes. Which readers a file gets, and a file's description, are raster_open.cpp's; the reads
// through whichever is set, raster_source.cpp's.
#pragma once
#include <memory>
#include <mutex>
#include <string>

#include "libpyramid/input/decoded_rows.hpp"
#include "libpyramid/input/image_io_module.hpp"
#include "libpyramid/input/raster_info.hpp"
#include "libpyramid/input/raster_mosaic.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/input/raw_grid_reader.hpp"
#include "libpyramid/input/tiff_block_reader.hpp"
#include "libpyramid/input/tiff_mask_reader.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"

namespace pyramid {

struct RasterSource::Impl {
    std::string path;
    int cacheMegabytes = 256;
    double heightScale = 1.0; // a file's stored heights to the ground's unit (Georeference::heightsToGround)
    // A file's own channels' scaling (RasterInfo::scaling), applied by readFloat before the unit;
    // a mosaic's members apply theirs, so a mosaic has none of its own here.
    std::vector<ValueScaling> scaling;
    // Direct readers, set for the files they can read, tried in this order.
    std::unique_ptr<TiffPixelReader> floats; // uncompressed float32 TIFF: one pread per row
    std::unique_ptr<TiffBlockReader> blocks; // lossless grey, grey+alpha, RGB(A) TIFF: libtiff, block by block
    std::unique_ptr<TiffPixelReader> pixels; // uncompressed 8/16-bit TIFF: one pread per row
    std::unique_ptr<RawGridReader> raw;      // SRTM .hgt, ESRI .hdr-labelled grids: one pread per row
    std::unique_ptr<DecodedRows> decoded;    // 8/16-bit PNG, 8-bit JPEG or an ASCII grid, decoded whole
    std::unique_ptr<TiffMaskReader> mask;    // a TIFF's transparency mask (RasterInfo::mask), beside its reader
    std::unique_ptr<RasterMosaic> mosaic;    // or many files on one grid, each read as above
    std::shared_ptr<const RasterPixels> computed; // or pixels a caller computes
    const BytePixels* computedBytes = nullptr;    // `computed`, when it computes bytes
    // Everything else goes through OpenImageIO's ImageCache in the image I/O module, opened
    // the first time a read needs it (or at once when no direct reader knows the file).
    mutable std::once_flag moduleOnce;
    mutable std::unique_ptr<ModuleImage> moduleImage;
    mutable std::string moduleError;

    // The module's image, opened the first time it is asked for. Throws Error("PATH: ...") when
    // the module cannot read the file.
    const ModuleImage& viaModule() const;
    // Channels [c0, c1) of a window through the module, in the file's own sample type `type`.
    void readModule(int x0, int y0, int x1, int y1, int c0, int c1, SampleType type, void* out) const;
};

} // namespace pyramid
