// Where a residual pyramid's heights come from: the encoder asks a HeightSource for the
// heights of finest-grid positions, and a planar raster (encode/dem/dem_sampling.hpp), a cube
// face of a planet (encode/dem/sphere_dem_encoder.cpp) or a caller's own source answers.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pyramid {

// Heights of finest-grid samples x0 + i*stride (0 <= i < nx), y0 + j*stride (0 <= j < ny),
// all inside [0, N]. valid: 1 = a height, 0 = nodata (2 is used by the encoder for filled).
struct SourceGrid {
    int64_t x0 = 0, y0 = 0, stride = 1;
    int64_t nx = 0, ny = 0;
    std::vector<float> height;
    std::vector<uint8_t> valid;
    // Where each row starts in height and valid: empty when the rows lie one after another, as in
    // every grid a HeightSource fills. Else one offset per row: the encoder's in-memory grid of a
    // map that covers a part of it stores only the rows valid heights can reach (and the root's),
    // the others sharing one row of nodata that is never written.
    std::vector<size_t> rows;

    size_t rowStart(int64_t fy) const {
        const auto j = static_cast<size_t>((fy - y0) / stride);
        return rows.empty() ? j * static_cast<size_t>(nx) : rows[j];
    }
    size_t column(int64_t fx) const { return static_cast<size_t>((fx - x0) / stride); }
    size_t index(int64_t fx, int64_t fy) const { return rowStart(fy) + column(fx); }
};

// Where a residual pyramid's heights come from: fills grid.height and grid.valid for the
// positions grid describes (allocating them). Thread-safe.
class HeightSource {
public:
    virtual ~HeightSource() = default;
    virtual void sample(SourceGrid& grid) const = 0;
    // False only when no position of [x0, x1] x [y0, y1] (finest-grid coordinates, inclusive;
    // beyond [0, N] where edges are folded) can have a valid height: the encoder then codes the
    // tiles there as residual 0 (what all-nodata samples give) without sampling them. Claims
    // nothing by default.
    virtual bool mayHaveHeights(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
        (void)x0, (void)y0, (void)x1, (void)y1;
        return true;
    }
    // The same for heights that belong at `level` or deeper: a source of several resolutions (a
    // fine inset over a coarse base) answers false where only coarser inputs are, and the encoder
    // then goes no deeper there (residual 0: the coarser level's heights, upsampled). By default,
    // every height belongs at every level.
    virtual bool mayHaveHeightsAt(int level, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
        (void)level;
        return mayHaveHeights(x0, y0, x1, y1);
    }
    // Whether mayHaveHeightsAt may answer false where mayHaveHeights does not (inputs of several
    // resolutions): the encoder then samples its in-memory grid of levels 0..C only as densely as
    // the levels encoded there need (residual_reach.hpp, blockLevels). False by default.
    virtual bool severalLevels() const { return false; }
};

} // namespace pyramid
