// Where a spherical DEM puts a map, checked through its heights: a smooth known function of the
// position written into a georeferenced map, and the check that the pyramid built from the map
// reconstructs that function at the face vertices that lie on it.
#pragma once
#include <array>
#include <functional>
#include <string>

#include "libpyramid/encode/dem/sphere_dem_encoder.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid::test {

// The unit vector of a geodetic direction (latitude and longitude in degrees, on the sphere).
std::array<double, 3> unitVector(double lat, double lon);

// The cube face whose centre is nearest to a point.
int faceOf(double lat, double lon);

// Heights that change by 10 m per kilometre of arc, eastwards and northwards from a centre,
// smooth everywhere (a linear function of the unit vector, poles included): the second
// derivative along a great circle is at most 63.71 km per radian squared.
struct Slope {
    std::array<double, 3> east, north, centre;
    Slope(double lat, double lon);
    double operator()(double lat, double lon) const;
};

// Spherical DEM options for placement checks: 32-sample tiles, roots of 4, a 0.25 m scale.
SphericalDemOptions placementOptions(int maxLevel);

// The position of a geodetic point in a map's pixel-centre coordinates ((0, 0) is the centre of
// the first pixel), as the test lays the map out; false where the point has none.
using PixelOf = std::function<bool(const GeodeticPoint& p, double& col, double& row)>;
using HeightAt = std::function<double(double lat, double lon)>;

// Builds the face under (lat0, lon0) of `map` to `maxLevel` and checks every finest vertex whose
// point lies at least 1.5 pixels inside the W x H map (by `pixelOf`) against `height`: at least
// 40 such vertices, none further than `tolerance` from it, and a CRS in the report.
void expectPlaced(const std::string& map, double lat0, double lon0, int maxLevel, const PixelOf& pixelOf, int W,
                  int H, const HeightAt& height, double tolerance, double scale = 0.25);

} // namespace pyramid::test
