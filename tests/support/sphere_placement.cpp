#include "tests/support/sphere_placement.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "libpyramid/sphere/cube_faces.hpp"
#include "tests/support/paths.hpp"

namespace pyramid::test {

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

} // namespace

std::array<double, 3> unitVector(double lat, double lon) {
    return {std::cos(lat * kDegree) * std::cos(lon * kDegree), std::cos(lat * kDegree) * std::sin(lon * kDegree),
            std::sin(lat * kDegree)};
}

int faceOf(double lat, double lon) {
    const auto u = unitVector(lat, lon);
    const int axis = std::fabs(u[2]) >= std::max(std::fabs(u[0]), std::fabs(u[1])) ? 2 : std::fabs(u[0]) >= std::fabs(u[1]) ? 0 : 1;
    if (axis == 2) {
        return u[2] > 0 ? 1 : 6;
    }
    return axis == 0 ? (u[0] > 0 ? 3 : 5) : (u[1] > 0 ? 4 : 2);
}

Slope::Slope(double lat, double lon)
    : east{-std::sin(lon * kDegree), std::cos(lon * kDegree), 0.0},
      north{-std::sin(lat * kDegree) * std::cos(lon * kDegree), -std::sin(lat * kDegree) * std::sin(lon * kDegree),
            std::cos(lat * kDegree)},
      centre(unitVector(lat, lon)) {}

double Slope::operator()(double lat, double lon) const {
    const auto u = unitVector(lat, lon);
    double e = 0, n = 0;
    for (int k = 0; k < 3; ++k) {
        e += east[k] * (u[k] - centre[k]);
        n += north[k] * (u[k] - centre[k]);
    }
    return 6371.0 * 10.0 * (0.8 * e + 0.6 * n); // 10 m per km of arc
}

SphericalDemOptions placementOptions(int maxLevel) {
    SphericalDemOptions o;
    o.dem.tileSize = 32;
    o.dem.rootTileSize = 4;
    o.dem.maxLevel = maxLevel;
    o.dem.scale = 0.25;
    return o;
}

void expectPlaced(const std::string& map, double lat0, double lon0, int maxLevel, const PixelOf& pixelOf, int W,
                  int H, const HeightAt& height, double tolerance, double scale) {
    TempDir out;
    SphericalDemOptions o = placementOptions(maxLevel);
    o.dem.scale = scale;
    const int face = faceOf(lat0, lon0);
    o.faces = {face};
    const PlanetBody body = PlanetBody::parse(o.body);
    const int64_t N = int64_t{4} << maxLevel;
    const int n = 32;
    int checked = 0;
    double worst = 0.0;
    o.reconstruction = [&](int f, int l, int tx, int ty, const std::vector<float>& z) {
        if (l != maxLevel) {
            return;
        }
        for (int j = 2; j < n + 3; ++j) {
            for (int i = 2; i < n + 3; ++i) {
                const FaceSample s{f, tx * n + i - 2, ty * n + j - 2};
                const GeodeticPoint g = body.geodeticOf(direction(cubePoint(FaceGrid{N, FaceGridKind::Vertices}, s)));
                double col = 0, row = 0;
                if (!pixelOf(g, col, row) || col < 1.0 || row < 1.0 || col > W - 2.0 || row > H - 2.0) {
                    continue;
                }
                ++checked;
                const double d = std::fabs(z[static_cast<size_t>(i + j * (n + 5))] - height(g.latitude, g.longitude));
                worst = std::max(worst, d);
            }
        }
    };
    const SphericalDemReport r = encodeSphericalDem(map, out.file("dem"), o);
    EXPECT_GT(checked, 40) << "too few vertices on the map";
    EXPECT_LE(worst, tolerance) << "on face " << face << ", " << checked << " vertices";
    EXPECT_FALSE(r.crs.empty());
}

} // namespace pyramid::test
