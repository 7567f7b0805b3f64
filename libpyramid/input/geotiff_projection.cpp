#include "libpyramid/input/geotiff_projection.hpp"

#include <geotiff/geokeys.h>
#include <geotiff/geovalues.h>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <string>

namespace pyramid {

namespace {

// Readable names of the GeoTIFF coordinate transformations, for the messages that refuse them;
// null for a code GeoTIFF does not define.
const char* methodName(int ct) {
    static const std::map<int, const char*> names{
        {CT_TransverseMercator, "transverse Mercator"},
        {CT_TransvMercator_Modified_Alaska, "modified transverse Mercator (Alaska)"},
        {CT_ObliqueMercator, "Hotine oblique Mercator"},
        {CT_ObliqueMercator_Laborde, "Laborde oblique Mercator"},
        {CT_ObliqueMercator_Rosenmund, "Swiss oblique cylindrical"},
        {CT_ObliqueMercator_Spherical, "spherical oblique Mercator"},
        {CT_Mercator, "Mercator"},
        {CT_LambertConfConic_2SP, "Lambert conformal conic (2SP)"},
        {CT_LambertConfConic_1SP, "Lambert conformal conic (1SP)"},
        {CT_LambertAzimEqualArea, "Lambert azimuthal equal-area"},
        {CT_AlbersEqualArea, "Albers equal-area"},
        {CT_AzimuthalEquidistant, "azimuthal equidistant"},
        {CT_EquidistantConic, "equidistant conic"},
        {CT_Stereographic, "stereographic"},
        {CT_PolarStereographic, "polar stereographic"},
        {CT_ObliqueStereographic, "oblique stereographic"},
        {CT_Equirectangular, "projected equirectangular"},
        {CT_CassiniSoldner, "Cassini-Soldner"},
        {CT_Gnomonic, "gnomonic"},
        {CT_MillerCylindrical, "Miller cylindrical"},
        {CT_Orthographic, "orthographic"},
        {CT_Polyconic, "polyconic"},
        {CT_Robinson, "Robinson"},
        {CT_Sinusoidal, "sinusoidal"},
        {CT_VanDerGrinten, "Van der Grinten"},
        {CT_NewZealandMapGrid, "New Zealand map grid"},
        {CT_TransvMercator_SouthOrientated, "south-orientated transverse Mercator"},
        {CT_CylindricalEqualArea, "cylindrical equal-area"},
        {CT_HotineObliqueMercatorAzimuthCenter, "Hotine oblique Mercator (azimuth at centre)"},
    };
    const auto it = names.find(ct);
    return it == names.end() ? nullptr : it->second;
}

// EPSG:3857 and its retired aliases: spherical Mercator formulas applied to WGS84 coordinates,
// which no GeoTIFF coordinate transformation code describes.
bool isWebMercator(int pcs) { return pcs == 3857 || pcs == 3785 || pcs == 900913; }

// Whether a projection parameter is an angle (in the geographic CRS's unit when given by keys).
bool angularParameter(int key) {
    switch (key) {
    case ProjNatOriginLatGeoKey:
    case ProjNatOriginLongGeoKey:
    case ProjFalseOriginLatGeoKey:
    case ProjFalseOriginLongGeoKey:
    case ProjCenterLatGeoKey:
    case ProjCenterLongGeoKey:
    case ProjStdParallel1GeoKey:
    case ProjStdParallel2GeoKey:
    case ProjStraightVertPoleLongGeoKey:
        return true;
    default:
        return false;
    }
}

} // namespace

Projection projectionOf(const GTIFDefn& d, int pcs, bool byKeys, double angleDegrees) {
    Projection p;
    if (d.CTProjection == KvUserDefined) {
        p.method = ProjectionMethod::None;
        p.name = "none";
    } else if (const char* name = methodName(d.CTProjection)) {
        p.name = name;
    } else {
        p.name = std::string("unknown (") + (byKeys ? "ProjCoordTransGeoKey " : "EPSG method ") +
                 std::to_string(d.CTProjection) + ")";
    }
    std::map<int, double> parm;
    for (int k = 0; k < d.nParms && k < MAX_GTIF_PROJPARMS; ++k) {
        if (d.ProjParmId[k] != 0) {
            parm[d.ProjParmId[k]] = d.ProjParm[k] * (angularParameter(d.ProjParmId[k]) ? angleDegrees : 1.0);
        }
    }
    auto get = [&](std::initializer_list<int> keys, double fallback) {
        for (const int key : keys) {
            if (const auto it = parm.find(key); it != parm.end()) {
                return it->second;
            }
        }
        return fallback;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    p.originLatitude = get({ProjNatOriginLatGeoKey, ProjFalseOriginLatGeoKey, ProjCenterLatGeoKey}, 0.0);
    p.originLongitude = get({ProjNatOriginLongGeoKey, ProjFalseOriginLongGeoKey, ProjCenterLongGeoKey,
                             ProjStraightVertPoleLongGeoKey},
                            0.0);
    p.scale = get({ProjScaleAtNatOriginGeoKey, ProjScaleAtCenterGeoKey}, 1.0);
    p.standardParallel1 = get({ProjStdParallel1GeoKey}, nan);
    p.standardParallel2 = get({ProjStdParallel2GeoKey}, nan);
    p.falseEasting = get({ProjFalseEastingGeoKey, ProjFalseOriginEastingGeoKey, ProjCenterEastingGeoKey}, 0.0);
    p.falseNorthing = get({ProjFalseNorthingGeoKey, ProjFalseOriginNorthingGeoKey, ProjCenterNorthingGeoKey}, 0.0);
    if (isWebMercator(pcs)) {
        p.method = ProjectionMethod::WebMercator;
        p.name = "popular visualisation pseudo-Mercator";
    } else if (d.CTProjection == CT_TransverseMercator) {
        p.method = ProjectionMethod::TransverseMercator;
    } else if (d.CTProjection == CT_PolarStereographic) {
        p.method = ProjectionMethod::PolarStereographic;
    } else if (d.CTProjection == CT_LambertConfConic_1SP || d.CTProjection == CT_LambertConfConic_2SP) {
        p.method = ProjectionMethod::LambertConformalConic;
    } else if (d.CTProjection == CT_Mercator) {
        p.method = ProjectionMethod::Mercator;
    }
    return p;
}

double angularUnit(const GeoTiffLibrary& lib, GTIF* gtif, const GTIFDefn& d, std::string& why) {
    unsigned short key = 0;
    const bool given = lib.keyGet(gtif, GeogAngularUnitsGeoKey, &key, 0, 1) == 1;
    if (d.UOMAngle == KvUserDefined) {
        if (!given) {
            return 1.0; // a user-defined geographic CRS that names no unit: degrees, as GDAL reads it
        }
        double radians = 0.0;
        if (lib.keyGet(gtif, GeogAngularUnitSizeGeoKey, &radians, 0, 1) == 1 && std::isfinite(radians) &&
            radians > 0.0) {
            return radians * 180.0 / 3.14159265358979323846;
        }
        why = "has a user-defined GeogAngularUnitsGeoKey (32767) without GeogAngularUnitSizeGeoKey, its size in "
              "radians";
        return 1.0;
    }
    const int code = d.UOMAngle;
    // EPSG's sexagesimal notations (DDD.MMSSsss and the like) are not multiples of an angle.
    if (code == 9110 || code == 9111 || (code >= 9115 && code <= 9121)) {
        why = "has GeogAngularUnitsGeoKey " + std::to_string(code) +
              ", a sexagesimal notation, not a unit of angle: no affine transform maps pixels to it";
        return 1.0;
    }
    const bool degree = code == 9102 || code == 9107 || code == 9108 || code == 9122; // and its notations
    if (d.UOMAngleInDegrees == 1.0 && !degree) {
        why = "has GeogAngularUnitsGeoKey " + std::to_string(code) + ", which is no angular unit of the EPSG database";
        return 1.0;
    }
    return d.UOMAngleInDegrees > 0.0 ? d.UOMAngleInDegrees : 1.0;
}

} // namespace pyramid
