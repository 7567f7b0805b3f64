#include "libpyramid/face_sampler.hpp"

#include <algorithm>

namespace pyramid {

FaceSampler::FaceSampler(const EquirectSampler& map, const PlanetBody& body, int face, FaceGrid grid, double scale)
    : map_(map), body_(body), face_(face), grid_(grid), scale_(scale) {
    (void)cubePoint(grid_, FaceSample{face_, 0, 0}); // rejects a bad face number here, not mid-run
}

GeodeticPoint FaceSampler::geodeticOf(int64_t x, int64_t y) const {
    return body_.geodeticOf(direction(cubePoint(grid_, FaceSample{face_, x, y})));
}

void FaceSampler::sample(int64_t x0, int64_t y0, int64_t stride, int64_t nx, int64_t ny, float* out,
                         uint8_t* valid) const {
    const int channels = map_.channels();
    // Rows in bands of about 64k points: one map window per band when the band is compact.
    const int64_t bandRows = std::max<int64_t>(1, 65536 / std::max<int64_t>(nx, 1));
    std::vector<GeodeticPoint> points;
    for (int64_t j0 = 0; j0 < ny; j0 += bandRows) {
        const int64_t rows = std::min(bandRows, ny - j0);
        points.resize(static_cast<size_t>(rows * nx));
        for (int64_t j = 0; j < rows; ++j) {
            for (int64_t i = 0; i < nx; ++i) {
                points[static_cast<size_t>(j * nx + i)] = geodeticOf(x0 + i * stride, y0 + (j0 + j) * stride);
            }
        }
        float* o = out + static_cast<size_t>(j0 * nx * channels);
        map_.sample(points.data(), points.size(), o, valid + j0 * nx);
        if (scale_ != 1.0) {
            for (size_t k = 0; k < points.size() * static_cast<size_t>(channels); ++k) {
                o[k] = static_cast<float>(static_cast<double>(o[k]) * scale_);
            }
        }
    }
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
