#include "libpyramid/sphere/face_locate.hpp"

#include <cmath>

namespace pyramid {

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

} // namespace

std::array<double, 3> directionOf(const PlanetBody& body, const GeodeticPoint& p) {
    const double squash = (1.0 - body.flattening()) * (1.0 - body.flattening());
    const double lat = p.latitude * kDegree, lon = p.longitude * kDegree;
    return {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), squash * std::sin(lat)};
}

} // namespace pyramid
