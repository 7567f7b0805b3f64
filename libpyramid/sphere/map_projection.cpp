#include "libpyramid/sphere/map_projection.hpp"

#include <GeographicLib/LambertConformalConic.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/PolarStereographic.hpp>
#include <GeographicLib/TransverseMercator.hpp>

#include <cmath>

#include "formats/error.hpp"

namespace pyramid {

namespace {

using GeographicLib::Math;

// GeographicLib's projections about a central meridian (TransverseMercator,
// LambertConformalConic), whose x and y count from an origin of their own (the equator, the
// cone's central parallel): shifted so that the CRS's origin lies at its false easting and
// northing.
template <class Projector>
class CentralMeridianProjection final : public MapProjection {
public:
    CentralMeridianProjection(const Projection& p, const Projector& projector) : p_(p), projector_(projector) {
        projector_.Forward(p_.originLongitude, p_.originLatitude, p_.originLongitude, originX_, originY_);
    }
    bool forward(double lat, double lon, double& x, double& y) const override {
        projector_.Forward(p_.originLongitude, lat, lon, x, y);
        x += p_.falseEasting - originX_;
        y += p_.falseNorthing - originY_;
        return std::isfinite(x) && std::isfinite(y);
    }
    void reverse(double x, double y, double& lat, double& lon) const override {
        projector_.Reverse(p_.originLongitude, x - p_.falseEasting + originX_, y - p_.falseNorthing + originY_, lat,
                           lon);
    }

private:
    Projection p_;
    Projector projector_;
    double originX_ = 0.0, originY_ = 0.0;
};

// Lambert conformal conic, 2SP: two standard parallels (scale 1 on both); 1SP: the natural
// origin's latitude, scale k0 there.
GeographicLib::LambertConformalConic cone(const Georeference& g) {
    const Projection& p = g.projection;
    if (std::isfinite(p.standardParallel1)) {
        const double sp2 = std::isfinite(p.standardParallel2) ? p.standardParallel2 : p.standardParallel1;
        return GeographicLib::LambertConformalConic(g.semiMajorAxis, g.flattening, p.standardParallel1, sp2, 1.0);
    }
    return GeographicLib::LambertConformalConic(g.semiMajorAxis, g.flattening, p.originLatitude, p.scale);
}

class PolarStereographicProjection final : public MapProjection {
public:
    explicit PolarStereographicProjection(const Georeference& g)
        : p_(g.projection), ps_(g.semiMajorAxis, g.flattening, std::fabs(p_.originLatitude) == 90.0 ? p_.scale : 1.0) {
        const double trueScale = std::isfinite(p_.standardParallel1) ? p_.standardParallel1
                                 : std::fabs(p_.originLatitude) != 90.0 ? p_.originLatitude
                                                                         : std::nan("");
        north_ = std::isfinite(trueScale) ? trueScale > 0.0 : p_.originLatitude > 0.0;
        if (std::isfinite(trueScale)) {
            // Variant B: true scale along a parallel (GeographicLib takes its latitude in the
            // northern hemisphere's terms).
            ps_.SetScale(std::fabs(trueScale), 1.0);
        }
    }
    bool forward(double lat, double lon, double& x, double& y) const override {
        if (lat == (north_ ? -90.0 : 90.0)) {
            return false; // the other pole lies at infinity
        }
        ps_.Forward(north_, lat, Math::AngDiff(p_.originLongitude, lon), x, y);
        x += p_.falseEasting;
        y += p_.falseNorthing;
        return std::isfinite(x) && std::isfinite(y);
    }
    void reverse(double x, double y, double& lat, double& lon) const override {
        ps_.Reverse(north_, x - p_.falseEasting, y - p_.falseNorthing, lat, lon);
        lon = Math::AngNormalize(lon + p_.originLongitude);
    }

private:
    Projection p_;
    GeographicLib::PolarStereographic ps_;
    bool north_ = true;
};

// Mercator: on the ellipsoid through the conformal latitude, or (Web Mercator) the sphere's
// formulas on geodetic latitudes (e = 0, k0 = 1).
class MercatorProjection final : public MapProjection {
public:
    MercatorProjection(const Georeference& g, bool web) : p_(g.projection), a_(g.semiMajorAxis) {
        const double e2 = web ? 0.0 : g.flattening * (2.0 - g.flattening);
        es_ = std::sqrt(e2);
        k0_ = web ? 1.0 : p_.scale;
        if (!web && std::isfinite(p_.standardParallel1)) {
            const double s = Math::sind(p_.standardParallel1);
            k0_ = Math::cosd(p_.standardParallel1) / std::sqrt(1.0 - e2 * s * s);
        }
    }
    bool forward(double lat, double lon, double& x, double& y) const override {
        if (!(std::fabs(lat) < 90.0)) {
            return false;
        }
        x = p_.falseEasting + a_ * k0_ * Math::AngDiff(p_.originLongitude, lon) * Math::degree();
        y = p_.falseNorthing + a_ * k0_ * std::asinh(Math::taupf(Math::tand(lat), es_));
        return std::isfinite(x) && std::isfinite(y);
    }
    void reverse(double x, double y, double& lat, double& lon) const override {
        const double psi = (y - p_.falseNorthing) / (a_ * k0_);
        lat = Math::atand(Math::tauf(std::sinh(psi), es_));
        lon = Math::AngNormalize(p_.originLongitude + (x - p_.falseEasting) / (a_ * k0_) / Math::degree());
    }

private:
    Projection p_;
    double a_, es_ = 0.0, k0_ = 1.0;
};

} // namespace

std::unique_ptr<MapProjection> MapProjection::of(const Georeference& crs, const std::string& path) {
    // The projection's longitudes count from the CRS's prime meridian: from Greenwich's here.
    Georeference g = crs;
    g.projection.originLongitude = Math::AngNormalize(g.projection.originLongitude + g.primeMeridian);
    switch (g.projection.method) {
    case ProjectionMethod::TransverseMercator:
        return std::make_unique<CentralMeridianProjection<GeographicLib::TransverseMercator>>(
            g.projection, GeographicLib::TransverseMercator(g.semiMajorAxis, g.flattening, g.projection.scale));
    case ProjectionMethod::PolarStereographic:
        return std::make_unique<PolarStereographicProjection>(g);
    case ProjectionMethod::LambertConformalConic:
        return std::make_unique<CentralMeridianProjection<GeographicLib::LambertConformalConic>>(g.projection, cone(g));
    case ProjectionMethod::Mercator:
        return std::make_unique<MercatorProjection>(g, false);
    case ProjectionMethod::WebMercator:
        return std::make_unique<MercatorProjection>(g, true);
    case ProjectionMethod::None:
        fail(path, g.crsText() + " names no projection method: " +
                       (g.epsg > 0 ? "ProjectedCSTypeGeoKey " + std::to_string(g.epsg) +
                                         " is not in the EPSG database libgeotiff reads"
                                   : std::string("neither ProjectionGeoKey nor ProjCoordTransGeoKey is given")));
    case ProjectionMethod::Other:
        break;
    }
    fail(path, g.crsText() + " is in the " + g.projection.name +
                   " projection, which is not supported; reproject it to EPSG:4326 (or to transverse Mercator/UTM, "
                   "polar stereographic, Lambert conformal conic or Mercator)");
}

} // namespace pyramid
