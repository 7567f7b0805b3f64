#include "libpyramid/sphere/planet_body.hpp"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/Geodesic.hpp>

#include <cmath>
#include <cstdio>

#include "formats/error.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid {

namespace {

// IUGG mean Earth radius R1 = (2a + b) / 3 of GRS80 (Moritz, "Geodetic Reference System 1980",
// Journal of Geodesy 74, 2000): the sphere of the same mean radius as the Earth.
constexpr double kEarthMeanRadius = 6371008.8;

// Moon and Mars: the IAU Working Group on Cartographic Coordinates and Rotational Elements
// (Archinal et al., "Report of the IAU WGCCRE: 2015", Celestial Mechanics and Dynamical
// Astronomy 130:22, 2018, table 5). The Moon's reference surface is a sphere of mean radius
// 1737.4 km (the one of the LRO/LOLA products). Mars: equatorial radius 3396.19 km, polar radius
// 3376.20 km (the MGS/MOLA ellipsoid).
constexpr double kMoonRadius = 1737400.0;
constexpr double kMarsEquatorialRadius = 3396190.0;
constexpr double kMarsPolarRadius = 3376200.0;

} // namespace

PlanetBody::PlanetBody(std::string name, double equatorialRadius, double flattening)
    : name_(std::move(name)), a_(equatorialRadius), f_(flattening > 1.0 ? 1.0 / flattening : flattening) {
    if (!(a_ > 0.0) || !std::isfinite(a_) || !(f_ >= 0.0) || !(f_ < 1.0)) {
        fail(name_, "needs a positive radius and a flattening in [0, 1) (or an inverse flattening > 1)");
    }
    squash_ = (1.0 - f_) * (1.0 - f_);
    geodesic_ = std::make_shared<const GeographicLib::Geodesic>(a_, f_);
}

PlanetBody PlanetBody::parse(const std::string& text) {
    if (text == "wgs84" || text == "WGS84") {
        return PlanetBody("wgs84", GeographicLib::Constants::WGS84_a(), GeographicLib::Constants::WGS84_f());
    }
    if (text == "sphere") {
        return PlanetBody("sphere", kEarthMeanRadius, 0.0);
    }
    if (text == "moon") {
        return PlanetBody("moon", kMoonRadius, 0.0);
    }
    if (text == "mars") {
        return PlanetBody("mars", kMarsEquatorialRadius, (kMarsEquatorialRadius - kMarsPolarRadius) / kMarsEquatorialRadius);
    }
    const size_t comma = text.find(',');
    if (comma == std::string::npos) {
        failOption("body", "'" + text + "' is not wgs84, sphere, moon, mars or A,F (radius in metres, flattening)");
    }
    const double a = parseOptionNumber(text.substr(0, comma), "body");
    const double f = parseOptionNumber(text.substr(comma + 1), "body");
    if (!(a > 0.0) || !(f >= 0.0) || f == 1.0) {
        failOption("body", "'" + text + "': the radius must be positive and the flattening in [0, 1) or an inverse flattening > 1");
    }
    return PlanetBody(text, a, f);
}

std::string PlanetBody::describe() const {
    char text[160];
    if (f_ == 0.0) {
        std::snprintf(text, sizeof text, "%s: sphere of radius %.1f m", name_.c_str(), a_);
    } else {
        std::snprintf(text, sizeof text, "%s: ellipsoid a = %.3f m, 1/f = %.9g", name_.c_str(), a_, 1.0 / f_);
    }
    return text;
}

GeodeticPoint PlanetBody::geodeticOf(const std::array<double, 3>& d) const {
    GeodeticPoint p;
    p.latitude = GeographicLib::Math::atan2d(d[2], squash_ * std::hypot(d[0], d[1]));
    p.longitude = GeographicLib::Math::atan2d(d[1], d[0]);
    return p;
}

double PlanetBody::distance(const GeodeticPoint& p, const GeodeticPoint& q) const {
    double s = 0.0;
    geodesic_->Inverse(p.latitude, p.longitude, q.latitude, q.longitude, s);
    return s;
}

} // namespace pyramid
