// Which float samples of a height raster are heights, which are missing and which are errors:
// the one rule of every reader of heights (preprocessDem, preprocessSphericalDem and `pyramid
// verify`, on one file or a mosaic).
//
// A sample equal to the nodata value in use is missing: any NaN when that value is NaN, +Inf or
// -Inf when it is that infinity, else the value rounded to float32. Any other NaN or infinity
// is an error naming the file, the column and the row: a height is a finite number.
#pragma once
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

namespace pyramid {

class RasterSource;

class HeightSamples {
public:
    explicit HeightSamples(std::optional<double> nodata);

    // A finite sample other than the nodata value: the common case, tested first.
    bool isHeight(float s) const { return std::isfinite(s) && !(finiteNodata_ && s == value_); }
    bool isNodata(float s) const {
        return nodata_ && (nanNodata_ ? std::isnan(s) : s == value_);
    }
    // Any sample of channel `channel` at (x, y) of `source`: true for a height, false for
    // nodata. Throws Error naming the file, column and row for a NaN or an infinity that is not
    // the nodata value.
    bool usable(float s, const RasterSource& source, int64_t x, int64_t y, int channel) const {
        if (isHeight(s)) {
            return true;
        }
        if (isNodata(s)) {
            return false;
        }
        failNotFinite(s, source, x, y, channel);
    }

    [[noreturn]] static void failNotFinite(float s, const RasterSource& source, int64_t x, int64_t y, int channel);

private:
    bool nodata_ = false;
    bool nanNodata_ = false;
    bool finiteNodata_ = false;
    float value_ = 0.0f;
};

// A nodata value as messages and reports write it: "nan", "inf", "-inf", or the number as
// numberText prints it. JSON has no NaN or infinity: reports give those three as text.
std::string nodataText(double value);

} // namespace pyramid
