// Where a geodetic point lies on the cube of a spherical pyramid: the inverse of the mapping
// the spherical encoders sample by (cube_faces.hpp: face plane -> cube direction;
// planet_body.hpp: direction -> geodetic position on the body).
#pragma once
#include <array>

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
FacePoint facePointOf(const std::array<double, 3>& d);

} // namespace pyramid
