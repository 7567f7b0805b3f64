// The body a spherical pyramid wraps: a sphere or an ellipsoid of revolution, and the map from
// a geocentric direction (a cube face sample) to the geodetic latitude and longitude of the
// body's surface point on that ray.
//
// Method: the ray t * d meets the ellipsoid (X^2 + Y^2) / a^2 + Z^2 / b^2 = 1 at one point P.
// P's geodetic latitude is the angle of the surface normal there, which is parallel to
// (X / a^2, Y / a^2, Z / b^2): tan(latitude) = (a / b)^2 Z / rho with rho = hypot(X, Y). The
// ratio Z / rho is the same for every point of the ray, so P itself is never computed:
//     latitude = atan2(dz, (1 - f)^2 hypot(dx, dy)),   longitude = atan2(dy, dx)
// in closed form (GeographicLib's Math::atan2d, exact at multiples of 45 degrees). This is the
// height-0 case of GeographicLib::Geocentric::Reverse, at a third of its cost; a test checks
// the result with Geocentric::Forward. On a sphere (f = 0) the geodetic latitude is the
// geocentric one: the original Proland mapping. On an oblate ellipsoid it is further from the
// equator, tan(geodetic) = tan(geocentric) / (1 - f)^2: about 0.19 degrees at 45 degrees on
// WGS84 (21 km on the ground).
//
// Longitudes are in degrees in [-180, 180]; +x is longitude 0, +y longitude 90 E, +z north.
#pragma once
#include <array>
#include <memory>
#include <string>

namespace GeographicLib {
class Geodesic;
}

namespace pyramid {

struct GeodeticPoint {
    double latitude = 0.0;  // degrees, geodetic
    double longitude = 0.0; // degrees, [-180, 180]
};

class PlanetBody {
public:
    // "wgs84" (the default), "sphere" (the Earth's mean radius, flattening 0), "moon", "mars",
    // or "A,F": equatorial radius A in metres and flattening F (F > 1 is taken as the inverse
    // flattening, e.g. "6378137,298.257223563"). Throws OptionError("body", ...) otherwise.
    static PlanetBody parse(const std::string& text);
    PlanetBody(std::string name, double equatorialRadius, double flattening);

    const std::string& name() const { return name_; }
    double equatorialRadius() const { return a_; } // metres
    double flattening() const { return f_; }
    double polarRadius() const { return a_ * (1.0 - f_); }
    std::string describe() const; // "WGS84 ellipsoid (a = 6378137 m, 1/f = 298.257223563)"

    // The geodetic position of the surface point on the ray from the centre along `d` (any
    // length but zero). Thread-safe.
    GeodeticPoint geodeticOf(const std::array<double, 3>& d) const;
    // Geodesic distance in metres between two surface points.
    double distance(const GeodeticPoint& p, const GeodeticPoint& q) const;

private:
    std::string name_;
    double a_;
    double f_;
    double squash_; // (1 - f)^2 = (b / a)^2
    std::shared_ptr<const GeographicLib::Geodesic> geodesic_;
};

} // namespace pyramid
