// Many georeferenced rasters read as one (RasterSource::openMosaic): files on one grid, as
// SRTM and Copernicus tiles, national sheets and scenes ship, joined without resampling.
//
// * The grid: every file has the same CRS, band count, sample type and pixel size, no
//   rotation, and lies at a whole number of pixels from the others (within 10^-6 pixel).
//   Anything else is refused, naming the file and what differs.
// * The mosaic covers the union of the files' extents; pixels no file holds are nodata.
// * The antimeridian: files of a geographic grid on which 360 degrees are a whole number of
//   pixels, lying on both sides of it (160..180 and -180..-160 E), are joined across it
//   (160..200 E) where that makes the mosaic narrower than their longitudes as labelled.
// * Overlaps: the first file in the list that has a value there (not its nodata) gives it;
//   colours by the whole pixel (input/colour_coverage.hpp: alpha 0, or nodata in every channel).
// * Nodata: the value the files declare (they must agree); when none declares one, NaN for
//   heights read as float32 (so gaps are holes, filled as any nodata) and 0 for colours (a
//   declared nodata no colour sample can hold: 0 too).
// * Masks: where a file has a transparency mask (RasterInfo::mask), the mosaic has one too,
//   which marks its gaps as well as the files' masked pixels.
// * Bounded: at most kOpenFiles files are open at once (least recently used closed first), each
//   with a share of the cache budget; a file is opened only when a read needs it.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "libpyramid/input/raster_info.hpp"
#include "libpyramid/support/open_set.hpp"

namespace pyramid {

class RasterSource;

// Where file b's pixel (0, 0) lies in file a's pixel coordinates (whole pixels) when the two
// lie on one grid: the same CRS and pixel size, no rotation, a whole number of pixels apart
// (within 10^-6 pixel); none otherwise. Bands, sample types and nodata are not compared. Both
// must be georeferenced.
std::optional<std::array<int64_t, 2>> offsetOnGrid(const RasterInfo& a, const RasterInfo& b);

// The files of a mosaic grouped by grid: each group holds the files one RasterMosaic can join
// (same CRS, bands, sample type, pixel size and nodata, at whole pixels from each other), in
// list order; groups come in the order of their first file. Throws Error naming a file that is
// missing, unreadable or without usable georeferencing.
std::vector<std::vector<std::string>> groupByGrid(const std::vector<std::string>& paths);

class RasterMosaic {
public:
    static constexpr size_t kOpenFiles = 64;

    // Describes every file (each is opened and closed once) and checks that they share a grid.
    // Throws Error naming the file that does not fit, is missing or has no georeferencing.
    RasterMosaic(const std::vector<std::string>& paths, int cacheMegabytes);
    ~RasterMosaic();

    const RasterInfo& info() const { return info_; }
    const std::string& name() const { return name_; }

    // As RasterSource's reads, over the mosaic's grid. Thread-safe.
    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const;
    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const;

    // The member that gives pixel (x, y) of `channel` (the first listed that holds a value
    // there) and the pixel in its own coordinates; the mosaic's name and (x, y) in a gap.
    struct Place {
        std::string path;
        int64_t column = 0;
        int64_t row = 0;
    };
    Place placeOf(int x, int y, int channel) const;

    struct Member {
        std::string path;
        int x = 0, y = 0; // its first pixel's place in the mosaic
        int width = 0, height = 0;
        std::optional<double> nodata;
        RasterInfo info; // as described when the mosaic was made (a reopened file is not described again)
    };
    const std::vector<Member>& members() const { return members_; }

private:
    std::shared_ptr<const RasterSource> openMember(size_t k) const;
    // Members whose pixels meet the window, in list order: from a grid of cells as large as the
    // largest member, each listing the members that meet it.
    std::vector<size_t> membersIn(int x0, int y0, int x1, int y1) const;
    // The window's pixels as `read` gives them, of which `values` from the `first` go to `out`
    // (with `covered`, the last of them is the mosaic's mask instead: 255 where a member gives the
    // pixel, 0 in a gap); has(member) gives {whether every pixel of the member counts, the values
    // a pixel of it stores (read asks for them), and where not every pixel counts, a predicate of
    // a pixel}.
    template <typename T, typename Read, typename Has>
    void compose(int x0, int y0, int x1, int y1, int first, int values, bool covered, T gap, Read read, Has has,
                 T* out) const;

    std::vector<Member> members_;
    RasterInfo info_;
    std::string name_;
    int memberCacheMegabytes_ = 4;
    uint16_t colourGap_ = 0; // a gap's colour: the declared nodata where a sample holds it, else 0
    int cellWidth_ = 1, cellHeight_ = 1, cellsAcross_ = 1;
    std::vector<std::vector<size_t>> cells_;
    std::unique_ptr<OpenSet<RasterSource>> open_; // members open now
};

} // namespace pyramid
