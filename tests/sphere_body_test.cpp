// Planet bodies: named constants, parsing, and the geocentric-direction -> geodetic mapping.
#include <gtest/gtest.h>

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Geocentric.hpp>

#include <cmath>

#include "formats/error.hpp"
#include "libpyramid/sphere/cube_faces.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(PlanetBody, NamedBodies) {
    const PlanetBody wgs = PlanetBody::parse("wgs84");
    EXPECT_EQ(wgs.equatorialRadius(), 6378137.0);
    EXPECT_DOUBLE_EQ(1.0 / wgs.flattening(), 298.257223563);
    const PlanetBody sphere = PlanetBody::parse("sphere");
    EXPECT_EQ(sphere.flattening(), 0.0);
    EXPECT_EQ(sphere.equatorialRadius(), 6371008.8);
    EXPECT_EQ(PlanetBody::parse("moon").equatorialRadius(), 1737400.0);
    EXPECT_EQ(PlanetBody::parse("moon").flattening(), 0.0);
    const PlanetBody mars = PlanetBody::parse("mars");
    EXPECT_EQ(mars.equatorialRadius(), 3396190.0);
    EXPECT_NEAR(mars.polarRadius(), 3376200.0, 1e-6);
    // Inverse flattening given as F > 1.
    const PlanetBody custom = PlanetBody::parse("6378137,298.257223563");
    EXPECT_DOUBLE_EQ(custom.flattening(), wgs.flattening());
    EXPECT_EQ(PlanetBody::parse("1000,0").flattening(), 0.0);
}

TEST(PlanetBody, BadBodiesAreOneLineErrors) {
    for (const char* text : {"venus", "", "1000", "-5,0", "1000,x", "x,0", "1000,1", "1000,-0.1", "inf,0"}) {
        try {
            PlanetBody::parse(text);
            ADD_FAILURE() << "accepted '" << text << "'";
        } catch (const Error& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.find('\n'), std::string::npos);
            EXPECT_EQ(m.rfind("body: ", 0), 0u) << m;
        }
    }
}

TEST(PlanetBody, FaceCentresAndPoles) {
    const PlanetBody wgs = PlanetBody::parse("wgs84");
    const struct {
        int face;
        double lat, lon;
    } expected[] = {{1, 90, 0}, {2, 0, -90}, {3, 0, 0}, {4, 0, 90}, {5, 0, 180}, {6, -90, 0}};
    for (const auto& e : expected) {
        const GeodeticPoint p = wgs.geodeticOf(faceDirection(e.face, 0.0, 0.0));
        EXPECT_NEAR(p.latitude, e.lat, 1e-12) << e.face;
        if (std::fabs(e.lat) < 90) {
            EXPECT_NEAR(std::fabs(p.longitude), std::fabs(e.lon), 1e-12) << e.face;
        }
    }
    // Face 3, u = 1 (its east edge), v = 0: longitude 45 E on the equator.
    const GeodeticPoint east = wgs.geodeticOf(faceDirection(3, 1.0, 0.0));
    EXPECT_NEAR(east.longitude, 45.0, 1e-12);
    EXPECT_NEAR(east.latitude, 0.0, 1e-12);
}

TEST(PlanetBody, GeodeticDiffersFromGeocentricAsGeodesySays) {
    // Face 3 at u = 0, v = 1 (the edge with face 1) has geocentric latitude 45 degrees.
    const std::array<double, 3> d = faceDirection(3, 0.0, 1.0);
    const GeodeticPoint sphere = PlanetBody::parse("sphere").geodeticOf(d);
    const PlanetBody wgs = PlanetBody::parse("wgs84");
    const GeodeticPoint geodetic = wgs.geodeticOf(d);
    EXPECT_NEAR(sphere.latitude, 45.0, 1e-12);
    // tan(geodetic) = tan(geocentric) / (1 - f)^2 for a point on the ellipsoid.
    const double f = wgs.flattening();
    const double expected = std::atan(1.0 / ((1 - f) * (1 - f))) / kDeg;
    EXPECT_NEAR(geodetic.latitude, expected, 1e-9);
    EXPECT_NEAR(geodetic.latitude - sphere.latitude, 0.19242, 1e-4);
    EXPECT_EQ(geodetic.longitude, sphere.longitude);
}

TEST(PlanetBody, SurfacePointLiesOnTheRay) {
    const PlanetBody wgs = PlanetBody::parse("wgs84");
    const GeographicLib::Geocentric earth = GeographicLib::Geocentric::WGS84();
    for (int face = 1; face <= 6; ++face) {
        for (double u : {-1.0, -0.3, 0.7}) {
            const std::array<double, 3> d = faceDirection(face, u, 0.4);
            const GeodeticPoint p = wgs.geodeticOf(d);
            double X, Y, Z;
            earth.Forward(p.latitude, p.longitude, 0.0, X, Y, Z);
            const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            const double r = std::sqrt(X * X + Y * Y + Z * Z);
            EXPECT_NEAR(X / r, d[0] / norm, 1e-12);
            EXPECT_NEAR(Y / r, d[1] / norm, 1e-12);
            EXPECT_NEAR(Z / r, d[2] / norm, 1e-12);
        }
    }
}

TEST(PlanetBody, GeodesicDistance) {
    const PlanetBody wgs = PlanetBody::parse("wgs84");
    // The WGS84 quarter meridian: 10 001 965.729 m.
    EXPECT_NEAR(wgs.distance({0, 0}, {90, 0}), 10001965.729, 1e-3);
    const PlanetBody moon = PlanetBody::parse("moon");
    EXPECT_NEAR(moon.distance({0, 0}, {0, 90}), 1737400.0 * M_PI / 2, 1e-6);
}

} // namespace
} // namespace pyramid
