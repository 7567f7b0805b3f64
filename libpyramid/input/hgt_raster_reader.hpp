// SRTM height files (`.hgt`): a square of N x N big-endian int16 heights in metres, north row
// first, nothing else in the file (N = 1201 for 3 arc-second cells, 3601 for 1 arc-second ones;
// any N from 2 whose 2 N^2 bytes are the file's size is taken). The file's name places it: its
// stem begins with the south-west corner of its 1 x 1 degree cell, `N46W122` (latitude 46 N,
// longitude 122 W; case ignored). The samples are points on the degree lines and between them,
// the edge rows and columns on the cell's edges (so neighbouring files share them): PixelIsPoint,
// one sample every 1 / (N - 1) degree, on WGS 84. -32768 marks a void (nodata). Read with one
// pread per row of a window (no cache of its own: the page cache does it).
#pragma once
#include <memory>
#include <string>

#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

class HgtRasterReader {
public:
    // Null when `path` is not named as a height file (`.hgt`, any case). Throws Error naming the
    // file when it is so named but its name places no cell or its size is no square of int16.
    static std::unique_ptr<HgtRasterReader> open(const std::string& path);
    ~HgtRasterReader();
    HgtRasterReader(const HgtRasterReader&) = delete;
    HgtRasterReader& operator=(const HgtRasterReader&) = delete;

    const RasterInfo& info() const { return info_; }
    // Columns [x0, x1) of rows [y0, y1), row-major, north first, as float32 by value (the
    // window is checked by the caller). False on a read error or a short file (errno set, 0
    // when short), as TiffPixelReader's reads. Thread-safe.
    bool readFloat(int x0, int y0, int x1, int y1, float* out) const;

private:
    HgtRasterReader() = default;
    std::string path_;
    int fd_ = -1;
    RasterInfo info_;
};

} // namespace pyramid
