#include "libpyramid/sphere/face_sampler.hpp"

#include <algorithm>
#include <cmath>

namespace pyramid {

FaceSampler::FaceSampler(const GeodeticMap& map, const PlanetBody& body, int face, FaceGrid grid, double scale)
    : map_(map), body_(body), face_(face), grid_(grid), scale_(scale) {
    (void)cubePoint(grid_, FaceSample{face_, 0, 0}); // rejects a bad face number here, not mid-run
}

GeodeticPoint FaceSampler::geodeticOf(int64_t x, int64_t y) const {
    return body_.geodeticOf(direction(cubePoint(grid_, FaceSample{face_, x, y})));
}

void FaceSampler::sample(int64_t x0, int64_t y0, int64_t stride, int64_t nx, int64_t ny, float* out,
                         uint8_t* valid) const {
    const int channels = map_.channels();
    // Blocks of at most kBlock x kBlock points: a block is compact on the map too, so the map
    // is read as one small window per block. (A whole face row would span a quarter of the
    // globe and many map rows: too wide a window, read point by point instead.) Each point's
    // value does not depend on the block it is read with.
    constexpr int64_t kBlock = 64;
    std::vector<GeodeticPoint> points;
    std::vector<float> values;
    std::vector<uint8_t> flags;
    for (int64_t bj = 0; bj < ny; bj += kBlock) {
        for (int64_t bi = 0; bi < nx; bi += kBlock) {
            const int64_t w = std::min(kBlock, nx - bi), h = std::min(kBlock, ny - bj);
            points.resize(static_cast<size_t>(w * h));
            for (int64_t j = 0; j < h; ++j) {
                for (int64_t i = 0; i < w; ++i) {
                    points[static_cast<size_t>(j * w + i)] = geodeticOf(x0 + (bi + i) * stride, y0 + (bj + j) * stride);
                }
            }
            values.resize(points.size() * static_cast<size_t>(channels));
            flags.resize(points.size());
            map_.sampleFor(4.0 * static_cast<double>(grid_.n) / static_cast<double>(stride), points.data(), points.size(), values.data(), flags.data());
            for (int64_t j = 0; j < h; ++j) {
                const size_t to = static_cast<size_t>((bj + j) * nx + bi);
                const size_t from = static_cast<size_t>(j * w);
                std::copy_n(&flags[from], w, valid + to);
                float* o = out + to * static_cast<size_t>(channels);
                const float* v = &values[from * static_cast<size_t>(channels)];
                for (size_t k = 0; k < static_cast<size_t>(w * channels); ++k) {
                    o[k] = scale_ == 1.0 ? v[k] : static_cast<float>(static_cast<double>(v[k]) * scale_);
                }
            }
        }
    }
}

bool FaceSampler::mayHaveValues(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    return mayHaveValuesFinerThan(0.0, x0, y0, x1, y1);
}

bool FaceSampler::mayHaveValuesFinerThan(double columnsAround, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const {
    if (columnsAround <= 0.0 && map_.everywhere()) {
        return true;
    }
    if (columnsAround > 0.0) {
        if (const std::optional<bool> known = map_.mayCoverFaceFinerThan(columnsAround, face_, grid_, x0, y0, x1, y1)) {
            return *known;
        }
    }
    const GeoBox b = faceGeographicBox(body_, face_, grid_, x0, y0, x1, y1);
    return columnsAround > 0.0 ? map_.mayCoverFinerThan(columnsAround, b.south, b.north, b.west, b.east, b.allLongitudes)
                               : map_.mayCover(b.south, b.north, b.west, b.east, b.allLongitudes);
}

GeoBox faceGeographicBox(const PlanetBody& body, int face, FaceGrid grid, int64_t x0, int64_t y0, int64_t x1,
                         int64_t y1) {
    const auto geodeticOf = [&](int64_t x, int64_t y) {
        return body.geodeticOf(direction(cubePoint(grid, FaceSample{face, x, y})));
    };
    // The outline, counter-clockwise in face samples, K points per side.
    constexpr int kSide = 64;
    std::vector<GeodeticPoint> outline;
    outline.reserve(4 * kSide);
    const auto along = [](int64_t a, int64_t b, int k) {
        return a + static_cast<int64_t>(std::llround(static_cast<double>(b - a) * k / kSide));
    };
    for (int k = 0; k < kSide; ++k) outline.push_back(geodeticOf(along(x0, x1, k), y0));
    for (int k = 0; k < kSide; ++k) outline.push_back(geodeticOf(x1, along(y0, y1, k)));
    for (int k = 0; k < kSide; ++k) outline.push_back(geodeticOf(along(x1, x0, k), y1));
    for (int k = 0; k < kSide; ++k) outline.push_back(geodeticOf(x0, along(y1, y0, k)));
    double longitude = outline[0].longitude; // unwrapped along the outline
    double south = 90.0, north = -90.0, west = longitude, east = longitude;
    double latitudeStep = 0.0, longitudeStep = 0.0; // the largest steps between neighbours
    for (size_t k = 0; k < outline.size(); ++k) {
        const GeodeticPoint& p = outline[k];
        const GeodeticPoint& next = outline[(k + 1) % outline.size()];
        south = std::min(south, p.latitude);
        north = std::max(north, p.latitude);
        west = std::min(west, longitude);
        east = std::max(east, longitude);
        double dl = next.longitude - p.longitude;
        dl -= 360.0 * std::round(dl / 360.0);
        latitudeStep = std::max(latitudeStep, std::fabs(next.latitude - p.latitude));
        longitudeStep = std::max(longitudeStep, std::fabs(dl));
        longitude += dl;
    }
    // An outline that winds around a pole holds it; one that comes within a step of a pole may
    // hold it too, and its longitudes say nothing.
    const bool aroundPole = std::fabs(longitude - outline[0].longitude) > 180.0;
    GeoBox b;
    b.south = south - 2.0 * latitudeStep;
    b.north = north + 2.0 * latitudeStep;
    if (b.north >= 90.0 || (aroundPole && b.north > 0.0)) {
        b.north = 90.0;
        b.allLongitudes = true;
    }
    if (b.south <= -90.0 || (aroundPole && b.south < 0.0)) {
        b.south = -90.0;
        b.allLongitudes = true;
    }
    b.allLongitudes = b.allLongitudes || aroundPole;
    const double margin = 2.0 * longitudeStep;
    b.west = west - margin;
    b.east = east + margin;
    return b;
}

GroundSampleDistance faceGroundSampleDistance(const PlanetBody& body, int face, const FaceGrid& grid) {
    const int64_t last = grid.kind == FaceGridKind::Vertices ? grid.n : grid.n - 1;
    constexpr int kProbes = 33;
    GroundSampleDistance g{1e300, 0.0};
    auto at = [&](int64_t x, int64_t y) {
        return body.geodeticOf(direction(cubePoint(grid, FaceSample{face, x, y})));
    };
    for (int b = 0; b < kProbes; ++b) {
        for (int a = 0; a < kProbes; ++a) {
            const int64_t x = std::min(last - 1, last * a / (kProbes - 1));
            const int64_t y = std::min(last - 1, last * b / (kProbes - 1));
            if (x < 0 || y < 0) {
                continue;
            }
            const GeodeticPoint p = at(x, y);
            for (const double d : {body.distance(p, at(x + 1, y)), body.distance(p, at(x, y + 1))}) {
                g.min = std::min(g.min, d);
                g.max = std::max(g.max, d);
            }
        }
    }
    if (g.max == 0.0) {
        g.min = 0.0;
    }
    return g;
}

} // namespace pyramid
