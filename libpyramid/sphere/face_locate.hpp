// Where a geodetic point lies on the cube of a spherical pyramid: the inverse of the mapping
// the spherical encoders sample by (cube_faces.hpp: face plane -> cube direction;
// planet_body.hpp: direction -> geodetic position on the body).
#pragma once
#include <array>
#include <cmath>

#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

struct FacePoint {
    int face = 1;             // 1..6
    double u = 0.0, v = 0.0;  // the face plane coordinates, in [-1, 1]
};

// A geocentric direction of the surface point at `p` on `body`: the ray PlanetBody::geodeticOf
// maps back to p. Its z over its horizontal length is (1 - f)^2 tan(latitude).
std::array<double, 3> directionOf(const PlanetBody& body, const GeodeticPoint& p);

// The face whose plane the direction crosses first (its largest component's axis and sign), and
// the plane coordinates of the crossing: faceDirection(face, u, v) is parallel to `d`. On an
// edge or a corner, the face of lowest number among those it touches.
inline FacePoint facePointOf(const std::array<double, 3>& d) {
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
