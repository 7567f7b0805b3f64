// How preprocessDem (and `pyramid verify`) turn an input raster into the heights of the
// pyramid's finest grid (doc/dem-encoding.md, "Sampling").
//
// The finest level has N intervals across the root quad, so N + 1 samples per side, on the
// vertices of the grid; sample (x, y) has y = 0 at the south. Its position in the input
// (column X, row Y, row 0 = north) is
//     X = x * Lx / N,   Y = (N - y) * Ly / N
// with Lx = Ly = max(W - 1, H - 1) by default (the aspect ratio is kept: the longer side spans
// the root quad, the input sits at the north-west corner and what lies beyond it is nodata), or
// Lx = W - 1, Ly = H - 1 with stretching. When W = H = N + 1, X = x and Y = N - y exactly: the
// finest grid is the input, sample for sample. Otherwise heights are interpolated bilinearly
// (in double precision, from the 2 x 2 input samples around (X, Y); a sample that needs a nodata
// neighbour with a non-zero weight is nodata).
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "libpyramid/encode/residual/height_source.hpp"
#include "libpyramid/input/raster_source.hpp"

namespace pyramid {

// The nodata value of a DEM source as preprocessDem's and `pyramid verify`'s --nodata give it:
// a number, "nan", "inf", "-inf" (input/nodata_text.hpp), or "none" (ignore the value the file
// declares); empty: what the file declares.
struct NodataChoice {
    std::optional<double> value;
    bool ignoreDeclared = false;
};
// Throws Error naming `option` when `text` is none of these.
NodataChoice parseNodataChoice(const std::string& text, const std::string& option);

struct DemGeometry {
    int64_t N = 0;  // finest intervals across the root quad
    int width = 0;  // input
    int height = 0;
    int64_t lx = 0; // input intervals spanned by the root quad, horizontally
    int64_t ly = 0; // and vertically
    bool exact() const { return width == N + 1 && height == N + 1; }
    std::string describe() const; // one sentence for reports
};

// Throws Error (naming `where`) for inputs smaller than 2 x 2.
DemGeometry makeDemGeometry(int width, int height, int64_t N, bool stretch, const std::string& where);

// The heights of a planar raster.
class DemSampler final : public HeightSource {
public:
    // `nodata`: the value that marks missing samples (NaN and infinities allowed), or none. Any
    // other NaN or infinity in the input is an error (input/height_samples.hpp).
    // `rootIntervals`: the intervals of level 0 across the root quad (level l has rootIntervals
    // << l), for mayHaveHeightsAt; 0 when the levels are not known (every height belongs at every
    // level).
    DemSampler(const RasterSource& source, const DemGeometry& geometry, int band, std::optional<double> nodata,
               int64_t rootIntervals = 0);

    const DemGeometry& geometry() const { return geometry_; }
    // Fills grid.height and grid.valid for the positions grid describes (allocates them).
    // Reads only the input window those positions need. Thread-safe.
    void sample(SourceGrid& grid) const override;
    // A raster of parts (RasterInfo::parts: a planar mosaic of several resolutions) has heights
    // only where a part is; a part of S samples across the root quad (the input's spanned
    // intervals over its pixels per sample) has heights of level l when l = 0 or S > rootIntervals
    // << (l - 1): its own resolution is finer than level l - 1's, the rule of the default
    // maxLevel. Without parts every position may have heights of every level.
    bool mayHaveHeights(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const override;
    bool mayHaveHeightsAt(int level, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const override;
    bool severalLevels() const override;

private:
    // Whether a part of level `level` or deeper (-1: any) meets finest positions [x0, x1] x [y0, y1].
    bool partMeets(int level, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const;
    int64_t rootIntervals_ = 0;
    const RasterSource& source_;
    DemGeometry geometry_;
    int band_;
    std::optional<double> nodata_;
};

} // namespace pyramid
