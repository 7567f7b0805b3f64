#include "libpyramid/encode/ortho/face_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

namespace pyramid {

namespace {

// std::lround (halves away from zero) without the library call, for the hot conversion of
// every finest pixel. For 0 <= x < 2^31 the conversion to an integer truncates, which is
// floor, and x - floor(x) is exact, so the result is lround's to the last bit; other values
// take lround itself.
inline long roundHalfAway(double x) {
    if (!(x >= 0.0 && x < 2147483648.0)) {
        return std::lround(x);
    }
    const long i = static_cast<long>(x);
    return i + (x - static_cast<double>(i) >= 0.5 ? 1 : 0);
}

// An interpolated input sample as 8 bits, 16-bit input rounded to the nearest 8-bit value.
inline uint8_t eightBits(double v, bool sixteen) {
    return static_cast<uint8_t>(roundHalfAway(v * 255.0 / (sixteen ? 65535.0 : 255.0)));
}

std::string degrees(double d) {
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", d);
    return text;
}

} // namespace

FacePixels::FacePixels(const RasterSource& source, const MapPlacement& placement, const PlanetBody& body, int face,
                       int channels, int64_t width)
    : channels_(channels), sixteen_(source.info().type == SampleType::UInt16), body_(body),
      map_(source, placement, 0, channels, SampleRead::UInt16, std::nullopt),
      face_(map_, body_, face, FaceGrid{width, FaceGridKind::PixelCentres}) {
    const int64_t W = width;
    const GeoExtent& extent = placement.extent;
    const std::string from = placement.map ? "the map in " + placement.crs + " within " : "the map's extent ";
    sampling_ = "face " + std::to_string(face) + " of the cube, " + std::to_string(W) + " pixels across, sampled " +
                "bilinearly on the " + body.name() + " body from " + from + degrees(extent.west) + "," +
                degrees(extent.south) + "," + degrees(extent.east) + "," + degrees(extent.north) +
                " (0 outside); borders from the neighbouring faces";
}

Image8 FacePixels::sample(int64_t x0, int64_t y0, int w, int h) const {
    Image8 out(w, h, channels_);
    // In bands of rows, so that the float samples never take much more memory than `out`.
    const int bandRows = std::max(1, 65536 / std::max(w, 1));
    std::vector<float> values;
    std::vector<uint8_t> valid;
    for (int j0 = 0; j0 < h; j0 += bandRows) {
        const int rows = std::min(bandRows, h - j0);
        const size_t points = static_cast<size_t>(w) * static_cast<size_t>(rows);
        values.resize(points * static_cast<size_t>(channels_));
        valid.resize(points);
        face_.sample(x0, y0 + j0, 1, w, rows, values.data(), valid.data());
        uint8_t* o = out.at(0, j0);
        for (size_t k = 0; k < points; ++k) {
            for (size_t c = 0; c < static_cast<size_t>(channels_); ++c) {
                const size_t s = k * static_cast<size_t>(channels_) + c;
                o[s] = valid[k] ? eightBits(static_cast<double>(values[s]), sixteen_) : 0; // nodata: as beyond the input
            }
        }
    }
    return out;
}

} // namespace pyramid
