// Rasters whose samples lie in the file uncompressed, at places a header elsewhere gives: an
// SRTM height file (hgt_grid.hpp: its name and size), an ESRI .hdr-labelled grid (.bil, .bip,
// .bsq, .flt, GTOPO30's .dem: esri_grid_header.hpp). The reader knows only where a sample lies
// and how it is stored; its description (RasterInfo: size, bands, type, nodata, place) is the
// header's. Read by one pread per row of a window (no cache of its own: the page cache does it).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

// Where sample (x, y) of band b lies: offset + y * rowBytes + x * pixelBytes + b * bandBytes.
struct RawGridLayout {
    uint64_t offset = 0;
    uint64_t rowBytes = 0;
    uint64_t pixelBytes = 0;
    uint64_t bandBytes = 0;
    bool bigEndian = false;
};

// A raw grid's description: what it holds, and where.
struct RawGrid {
    RasterInfo info; // type: one of UInt8, Int8, UInt16, Int16, UInt32, Int32, Float32, Float64
    RawGridLayout layout;
};

class RawGridReader {
public:
    // Opens `path` as `grid` describes it. Throws Error naming the file when it cannot be opened,
    // or is shorter than its last sample's end (a header that does not fit its data).
    static std::unique_ptr<RawGridReader> open(const std::string& path, const RawGrid& grid);
    ~RawGridReader();
    RawGridReader(const RawGridReader&) = delete;
    RawGridReader& operator=(const RawGridReader&) = delete;

    const RasterInfo& info() const { return grid_.info; }
    // Columns [x0, x1) of rows [y0, y1) of band `channel`, row-major, north first, as float32
    // (integers by value, float64 each to the nearest). The window is checked by the caller.
    // False on a read error (errno set; 0 when the file was cut short since it was opened), as
    // TiffPixelReader's reads. Thread-safe.
    bool readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const;
    // Bands [c0, c1), interleaved, as 16-bit values: 8 and 16-bit unsigned samples only (false
    // otherwise, or on a read error as above). Thread-safe.
    bool readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const;

private:
    RawGridReader() = default;
    // The bytes of band `channel`'s samples x0 .. x1 - 1 of row y, into `row` (one pixel stride
    // apart).
    bool readRow(int x0, int x1, int y, int channel, std::vector<uint8_t>& row) const;
    RawGrid grid_;
    int fd_ = -1;
    int sampleBytes_ = 0;
};

} // namespace pyramid
