// The finest pixels of a planar ortho pyramid, resampled from an image (ortho_levels.hpp,
// "Geometry"): pixel exact when the image is as wide and high as the finest level, otherwise
// bilinear at pixel centres, aspect kept (the image at the north-west corner, black and
// transparent beyond it) or stretched; 16-bit input brought to 8 bits.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "libpyramid/encode/ortho/pixel_source.hpp"
#include "libpyramid/input/raster_source.hpp"

namespace pyramid {

// An output row of 8-bit samples from its two interpolated input rows, `fy` of the way from
// `top` to `bottom` (values within [0, full]): v = top + (bottom - top) * fy, then
// v8 = lround(v * 255 / full) with full = 255 (8-bit input) or 65535 (16-bit).
void combineRows(const double* top, const double* bottom, double fy, double full, size_t count, uint8_t* row);

class PlanarPixels final : public PixelSource {
public:
    // The first `channels` channels of `source` (which must outlive this object) onto a finest
    // level `width` pixels across.
    PlanarPixels(const RasterSource& source, int channels, int64_t width, bool stretch);

    Image8 sample(int64_t x0, int64_t y0, int w, int h) const override;
    bool knownBlank(int64_t x0, int64_t y0, int64_t w, int64_t h) const override;
    int64_t margin(int) const override { return 0; }
    int64_t borderPixel(int64_t p, int64_t width) const override;
    const std::string& sampling() const override { return sampling_; }
    // A mosaic of several resolutions (RasterInfo::parts): a level W pixels across is needed by
    // the parts with more than W / 2 of their own pixels across the plane's longer side.
    bool severalLevels() const override;
    bool mayNeedLevel(int64_t levelWidth, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const override;
    // A coarser level reads only the input pixels its samples interpolate (readUInt16At).
    Image8 sampleAt(int64_t levelWidth, int64_t x0, int64_t y0, int w, int h) const override;
    // The input rows above those row y samples (bilinearly or as they are) are let go.
    void passedNorthOf(int64_t y) const override;

private:
    // Input position of output pixel centres along one axis.
    struct Axis {
        bool exact = false;
        double scale = 1.0; // input pixels per output pixel
        int input = 0;      // input pixels on this axis
        bool flip = false;  // rows: output y = 0 is the input's last row
        int64_t output = 0; // output pixels across (W)

        // Input coordinate of output pixel p's centre, minus 0.5 (so that integers are centres).
        double position(int64_t p) const {
            const int64_t q = flip ? output - 1 - p : p;
            return exact ? static_cast<double>(q) : (static_cast<double>(q) + 0.5) * scale - 0.5;
        }
        bool inside(double pos) const { return pos <= static_cast<double>(input) - 0.5; }
    };

    // sample() of an 8-bit input as wide as the finest level and as high or less (scale 1).
    Image8 sampleInPlace(int64_t x0, int64_t y0, int w, int h) const;

    // The axis of a level `levelWidth` pixels across (the finest one's width halved).
    Axis coarser(const Axis& finest, int64_t levelWidth) const;

    const RasterSource& source_;
    int channels_ = 0;
    bool stretch_ = false;
    bool sixteen_ = false;
    bool inPlace_ = false; // as wide as the finest level, as high or less (scale 1): sampleInPlace
    Axis ax_, ay_;
    std::string sampling_;
};

} // namespace pyramid
