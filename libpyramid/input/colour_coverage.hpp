// Which pixels of imagery hold a value: the rule every reader of several colour rasters as one
// follows (same-grid mosaics, planar mosaics of several grids, planets' maps). A pixel has no
// value when
//
// * its alpha is 0: the last channel, where the file declares it alpha (RasterInfo::alpha: a
//   fourth band of near-infrared, as NAIP's, is a colour, whatever its values); or
// * the file declares a nodata value and every channel of the pixel holds it (as GDAL's warper
//   writes `-dstnodata`: a black pixel of real imagery with one channel at 0 keeps its value); or
// * the file's transparency mask marks it (RasterInfo::mask: a TIFF's internal mask), which a
//   read of stored() channels gives after the image's own.
//
// The rule is over the whole pixel, whichever channels a read asks for: a mosaic never takes
// one channel from one file and the next from another. Samples are as readUInt16 gives them
// (8-bit 0..255, 16-bit 0..65535); a declared nodata that no sample of the file's type can hold
// (-9999 for bytes, 0.5) marks nothing.
#pragma once
#include <cmath>
#include <cstdint>
#include <optional>

#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

class ColourCoverage {
public:
    // The rule for `channels` channels of `type` (UInt8 or UInt16), the last one `alpha` or not,
    // with `nodata` declared, and a `mask` or not.
    ColourCoverage(int channels, bool alpha, SampleType type, std::optional<double> nodata, bool mask = false)
        : channels_(channels), alpha_(alpha && channels > 1), mask_(mask) {
        const std::optional<uint16_t> held = heldNodata(type, nodata);
        hasNodata_ = held.has_value();
        nodata_ = held.value_or(0);
    }
    explicit ColourCoverage(const RasterInfo& info)
        : ColourCoverage(info.channels, info.alpha, info.type, info.nodata, info.mask) {}

    // A declared nodata as a sample of `type` (UInt8 or UInt16) holds it; none when no sample can.
    static std::optional<uint16_t> heldNodata(SampleType type, const std::optional<double>& nodata) {
        const double top = type == SampleType::UInt8 ? 255.0 : 65535.0;
        if (nodata && *nodata >= 0.0 && *nodata <= top && std::floor(*nodata) == *nodata) {
            return static_cast<uint16_t>(*nodata);
        }
        return std::nullopt;
    }

    // The values of a pixel that has() reads: the file's channels, then its mask if it has one.
    int stored() const { return channels_ + (mask_ ? 1 : 0); }

    // Whether every pixel has a value (no alpha channel, no nodata a sample can hold, no mask).
    bool everywhere() const { return !alpha_ && !hasNodata_ && !mask_; }

    // Whether the pixel (stored() values, uint16_t or float holding whole numbers) has a value.
    template <typename T>
    bool has(const T* pixel) const {
        if ((alpha_ && pixel[channels_ - 1] == T{0}) || (mask_ && pixel[channels_] == T{0})) {
            return false;
        }
        if (!hasNodata_) {
            return true;
        }
        for (int c = 0; c < channels_; ++c) {
            if (pixel[c] != static_cast<T>(nodata_)) {
                return true;
            }
        }
        return false;
    }

private:
    int channels_;
    bool alpha_;
    bool mask_;
    bool hasNodata_ = false; // a declared nodata a sample can hold: nodata_
    uint16_t nodata_ = 0;
};

} // namespace pyramid
