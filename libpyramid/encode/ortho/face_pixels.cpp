#include "libpyramid/encode/ortho/face_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
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
                       int channels, int64_t width, const GeodeticMap* map)
    : channels_(channels), sixteen_(source.info().type == SampleType::UInt16), body_(body),
      own_(map ? nullptr : std::make_unique<EquirectSampler>(source, placement, 0, channels, SampleRead::UInt16,
                                                      source.info().nodata)),
      map_(map ? *map : *own_), face_(map_, body_, face, FaceGrid{width, FaceGridKind::PixelCentres}) {
    const int64_t W = width;
    const GeoExtent& extent = placement.extent;
    const std::string from = placement.map ? "the map in " + placement.crs + " within " : "the map's extent ";
    sampling_ = "face " + std::to_string(face) + " of the cube, " + std::to_string(W) + " pixels across, sampled " +
                "bilinearly on the " + body.name() + " body from " + from + degrees(extent.west) + "," +
                degrees(extent.south) + "," + degrees(extent.east) + "," + degrees(extent.north) +
                " (0 outside); borders from the neighbouring faces";
    for (int64_t w = W / 2; w >= 1 && w * 2 <= W && (W % (w * 2)) == 0; w /= 2) {
        coarser_.push_back(std::make_unique<FaceSampler>(map_, body_, face, FaceGrid{w, FaceGridKind::PixelCentres}));
    }
}

const FaceSampler& FacePixels::at(int64_t levelWidth) const {
    if (levelWidth == face_.grid().n) {
        return face_;
    }
    for (const auto& s : coarser_) {
        if (s->grid().n == levelWidth) {
            return *s;
        }
    }
    throw std::logic_error("FacePixels: no level " + std::to_string(levelWidth) + " pixels across");
}

bool FacePixels::mayNeedLevel(int64_t levelWidth, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    return at(levelWidth).mayHaveValuesFinerThan(2.0 * static_cast<double>(levelWidth), x0, y0, x1, y1);
}

Image8 FacePixels::sample(int64_t x0, int64_t y0, int w, int h) const { return sampleWith(face_, x0, y0, w, h); }

Image8 FacePixels::sampleAt(int64_t levelWidth, int64_t x0, int64_t y0, int w, int h) const {
    return sampleWith(at(levelWidth), x0, y0, w, h);
}

Image8 FacePixels::sampleWith(const FaceSampler& face, int64_t x0, int64_t y0, int w, int h) const {
    Image8 out(w, h, channels_);
    if (w <= 0 || h <= 0 || !face.mayHaveValues(x0, y0, x0 + w - 1, y0 + h - 1)) {
        return out; // wholly outside the map: 0 everywhere
    }
    // In blocks of columns of at least 16384 pixels, those the map cannot reach left 0 (each
    // pixel's value does not depend on the block it is sampled with); each block in bands of
    // rows, so that the float samples never take much more memory than `out`.
    const int blockColumns = std::max(64, 16384 / h);
    std::vector<float> values;
    std::vector<uint8_t> valid;
    for (int i0 = 0; i0 < w; i0 += blockColumns) {
        const int columns = std::min(blockColumns, w - i0);
        if (columns < w && !face.mayHaveValues(x0 + i0, y0, x0 + i0 + columns - 1, y0 + h - 1)) {
            continue;
        }
        const int bandRows = std::max(1, 65536 / columns);
        for (int j0 = 0; j0 < h; j0 += bandRows) {
            const int rows = std::min(bandRows, h - j0);
            const size_t points = static_cast<size_t>(columns) * static_cast<size_t>(rows);
            values.resize(points * static_cast<size_t>(channels_));
            valid.resize(points);
            face.sample(x0 + i0, y0 + j0, 1, columns, rows, values.data(), valid.data());
            for (int j = 0; j < rows; ++j) {
                uint8_t* o = out.at(i0, j0 + j);
                const size_t first = static_cast<size_t>(j) * static_cast<size_t>(columns);
                for (size_t k = 0; k < static_cast<size_t>(columns); ++k) {
                    for (size_t c = 0; c < static_cast<size_t>(channels_); ++c) {
                        const size_t s = (first + k) * static_cast<size_t>(channels_) + c;
                        // nodata: as beyond the input
                        o[k * static_cast<size_t>(channels_) + c] =
                            valid[first + k] ? eightBits(static_cast<double>(values[s]), sixteen_) : 0;
                    }
                }
            }
        }
    }
    return out;
}

} // namespace pyramid
