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

FacePoint facePointOf(const std::array<double, 3>& d) {
    const double ax = std::fabs(d[0]), ay = std::fabs(d[1]), az = std::fabs(d[2]);
    FacePoint f;
    // The inverses of cube_faces.hpp's table, face by face, in the order of the face numbers.
    if (az >= ax && az >= ay && d[2] > 0.0) { // 1: ( u,  v,  1)
        f = {1, d[0] / d[2], d[1] / d[2]};
    } else if (ay >= ax && ay >= az && d[1] < 0.0) { // 2: ( u, -1,  v)
        f = {2, d[0] / -d[1], d[2] / -d[1]};
    } else if (ax >= ay && ax >= az && d[0] > 0.0) { // 3: ( 1,  u,  v)
        f = {3, d[1] / d[0], d[2] / d[0]};
    } else if (ay >= ax && ay >= az && d[1] > 0.0) { // 4: (-u,  1,  v)
        f = {4, -d[0] / d[1], d[2] / d[1]};
    } else if (ax >= ay && ax >= az) { // 5: (-1, -u,  v)
        f = {5, d[1] / d[0], d[2] / -d[0]};
    } else { // 6: ( u, -v, -1)
        f = {6, d[0] / -d[2], d[1] / d[2]};
    }
    return f;
}

} // namespace pyramid
