// Where a raster lies on its planet: the coordinate reference system (CRS) of a GeoTIFF and the
// affine map from its pixels to that CRS, read with libgeotiff over libtiff (no GDAL): libtiff
// reads the tags, libgeotiff (loaded on demand, geotiff_library.hpp) interprets the keys.
//
// What is read: the GeoKeys (GTModelTypeGeoKey, the projected or geographic CRS, its datum's
// ellipsoid, units, prime meridian and projection parameters, normalised by libgeotiff's
// GTIFGetDefn, which looks EPSG codes up in PROJ's database; a user-defined angular unit's size,
// GeogAngularUnitSizeGeoKey, which it leaves unread, is read here), GTRasterTypeGeoKey, and the
// ModelTransformation tag or else one ModelTiepoint with ModelPixelScale. The raster-type
// convention is resolved here once: `pixelToCrs` always takes PixelIsArea coordinates, in which
// (0, 0) is the top-left corner of the first pixel and (col + 0.5, row + 0.5) the centre of
// pixel (col, row). A PixelIsPoint file's tiepoint names a pixel centre, so its transform is
// shifted by half a pixel (as GDAL does).
//
// Whether the spherical tools can place the raster is decided by them (sphere/map_projection.hpp):
// this file only describes.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace pyramid {

// The projection methods the spherical tools can forward-project; Other is anything else
// (`Projection::name` says which); None: the CRS names no method (a user-defined
// ProjectedCSTypeGeoKey without ProjectionGeoKey or ProjCoordTransGeoKey, or a code the EPSG
// database does not hold).
enum class ProjectionMethod {
    TransverseMercator,
    PolarStereographic,
    LambertConformalConic,
    Mercator,
    WebMercator,
    Other,
    None
};

// Parameters as libgeotiff normalises them: angles in degrees (those given by keys converted from
// the geographic CRS's angular unit, as GeoTIFF defines them), lengths in metres. Longitudes
// count from the CRS's prime meridian (Georeference::primeMeridian), as EPSG defines them: NTF
// (Paris) / Lambert zone II's central meridian is 0. NaN when the file does not give one.
struct Projection {
    ProjectionMethod method = ProjectionMethod::Other;
    std::string name; // "transverse Mercator", "Lambert azimuthal equal-area", ...
    double originLatitude = 0.0;  // natural origin, or the false origin of a two-parallel cone
    double originLongitude = 0.0; // central meridian (polar stereographic: the straight meridian)
    double scale = 1.0;           // at the natural origin
    double standardParallel1 = std::numeric_limits<double>::quiet_NaN();
    double standardParallel2 = std::numeric_limits<double>::quiet_NaN();
    double falseEasting = 0.0;
    double falseNorthing = 0.0;
};

// The unit a raster's heights are stored in (input/height_unit.hpp reads it from the GeoKeys).
struct HeightUnit {
    std::string name;    // "metre", "US survey foot"; "" when the code is not the database's
    double metres = 0.0; // one unit, in metres; 0 when unknown (the heights are read as stored)
    std::string source;  // where it was read: "EPSG:6360 (NAVD88 height (ftUS))", "VerticalUnitsGeoKey EPSG:9002"
};

struct Georeference {
    bool projected = false; // else geographic (longitude, latitude)
    int epsg = 0;           // the CRS's EPSG code (the projected one, or the geographic one); 0 if user-defined
    std::string name;       // "WGS 84", "WGS 84 / UTM zone 10N", or the file's citation
    double semiMajorAxis = 0.0; // of the datum's ellipsoid, metres
    double flattening = 0.0;
    double primeMeridian = 0.0; // degrees east of Greenwich (geographic longitudes count from it)
    double unitInMetres = 1.0;  // projected: one CRS unit (metre, US survey foot, ...)
    double unitInDegrees = 1.0; // geographic: one CRS unit (degree, grad, radian, a user-defined size)
    Projection projection;      // projected CRSs only
    // CRS x = t[0] + t[1] col + t[2] row, y = t[3] + t[4] col + t[5] row, in PixelIsArea pixel
    // coordinates (above). Geographic: x is the longitude, y the latitude.
    std::array<double, 6> pixelToCrs{0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
    bool pixelIsPoint = false; // what the file declares; already folded into pixelToCrs
    // The unit of the heights, where the vertical GeoKeys name one (else they are as stored).
    std::optional<HeightUnit> heightUnit;
    // Non-empty when the file is georeferenced in a way that places no pixel (geocentric model,
    // ground control points, a singular transform...): why.
    std::string problem;

    // "EPSG:32610 (WGS 84 / UTM zone 10N)", or the name alone when there is no code.
    std::string crsText() const;
    // What a stored height times gives it in the ground's unit (height_unit.hpp: the projected
    // CRS's unit, metres for a geographic one): 1 when the unit is unknown or the ground's.
    double heightsToGround() const;
    // The transform has no rotation or shear (t[2] = t[4] = 0).
    bool axisAligned() const { return pixelToCrs[2] == 0.0 && pixelToCrs[4] == 0.0; }
};

// The georeferencing of the TIFF at `path`, or nullopt when it is not a TIFF or has no GeoKey
// directory (a tiepoint without a CRS places nothing). Never throws; a georeferencing that
// cannot be used has `problem` set.
std::optional<Georeference> readGeoTiffGeoreference(const std::string& path);
// The same of a TIFF held in memory (the GeoTIFF a JPEG 2000 file's GeoJP2 box carries); nullopt
// also when the bytes are no TIFF.
std::optional<Georeference> readGeoTiffGeoreference(const std::vector<uint8_t>& tiff);

// The CRS a user names ("EPSG:32610", "epsg:4326"), looked up in the EPSG database through
// libgeotiff, as a file declaring that code alone would be read (pixelToCrs the identity).
// Throws OptionError("crs", ...) for text that is not such a code, or a code the database does
// not define as a projected or geographic CRS.
Georeference georeferenceOfCrs(const std::string& text);

// Whether two georeferencings are in the same CRS (coordinates of one are coordinates of the
// other): by code and name, as mosaics compare their files.
bool sameCrs(const Georeference& a, const Georeference& b);

} // namespace pyramid
