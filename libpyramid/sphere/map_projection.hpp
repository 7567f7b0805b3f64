// The map projections a georeferenced input may be in, forward (geodetic latitude and longitude
// -> projected metres) and reverse, on the input CRS's own ellipsoid (a, f), with its false
// easting and northing. GeographicLib does the ellipsoidal work:
//
// * transverse Mercator (UTM, Gauss-Krueger, national grids): GeographicLib::TransverseMercator
//   (Krueger's series, 5 nm within 3900 km of the central meridian); the northing counts from the
//   latitude of origin.
// * polar stereographic: GeographicLib::PolarStereographic. Variant A (latitude of origin +-90,
//   scale k0 at the pole) or variant B (a standard parallel of true scale, set with SetScale);
//   a latitude of origin other than +-90 is read as variant B's standard parallel, as GDAL does.
// * Lambert conformal conic, one or two standard parallels: GeographicLib::LambertConformalConic;
//   the northing counts from the latitude of the (false) origin.
// * Mercator on the ellipsoid (1SP with k0, 2SP with k0 = cos(phi1) / sqrt(1 - e^2 sin^2(phi1)))
//   in closed form: x = a k0 (lon - lon0), y = a k0 asinh(tan(chi)) where chi is the conformal
//   latitude, tan(chi) = GeographicLib::Math::taupf(tan(lat), e) (its inverse Math::tauf).
// * Web Mercator (EPSG:3857): the spherical formulas x = a (lon - lon0), y = a asinh(tan(lat))
//   applied to the ellipsoid's geodetic latitude (a = 6378137 m): what the EPSG method 1024
//   defines, neither conformal nor on the ellipsoid.
//
// Longitudes are geodetic, east of Greenwich: a CRS's central meridian, which counts from its prime
// meridian, is taken that far east of Greenwich (NTF (Paris) / Lambert zone II's 0 is 2.33722917
// degrees east). They are reduced to within 180 degrees of the central meridian. Anything else is
// refused by MapProjection::of, naming the CRS and the method (or the key a CRS without one lacks).
#pragma once
#include <memory>
#include <string>

#include "libpyramid/input/georeference.hpp"

namespace pyramid {

class MapProjection {
public:
    // The projection of a projected CRS. Throws Error(path, "EPSG:3035 (...) is in the Lambert
    // azimuthal equal-area projection, which is not supported; reproject it to EPSG:4326 ...")
    // for the others.
    static std::unique_ptr<MapProjection> of(const Georeference& crs, const std::string& path);
    virtual ~MapProjection() = default;

    // Metres east and north, false origin included. False where the point has no image (the poles
    // of Mercator).
    virtual bool forward(double latitude, double longitude, double& x, double& y) const = 0;
    virtual void reverse(double x, double y, double& latitude, double& longitude) const = 0;
};

} // namespace pyramid
