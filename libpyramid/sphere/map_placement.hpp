// Where a planet's map lies: the one decision of how a geodetic point finds its pixel, taken
// once per input from the file's georeferencing (input/georeference.hpp) or from --extent.
//
// * No georeferencing: a plate carree over the given extent (default: the globe), as always.
// * A geographic CRS whose pixels are aligned with the meridians, in degrees from Greenwich:
//   the same plate carree, over the extent the file declares. --extent may only repeat it
//   (within half a pixel, the ambiguity of grid- and cell-registered maps); else it is refused.
// * Any other geographic CRS (rotated, other angular units or prime meridian), and the projected
//   CRSs of map_projection.hpp: each point is forward-projected to CRS units and mapped to its
//   pixel by the inverse of the file's affine transform (GeoreferencedMap). --extent is refused.
//
// Geodetic coordinates on the input's datum are taken as the body's (doc/spherical.md, "The
// input's ellipsoid and --body"): no datum shift is applied.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "libpyramid/input/raster_info.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/map_projection.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

// A map placed by an affine transform of its CRS: projected, or geographic but not a plain
// plate carree.
class GeoreferencedMap {
public:
    // Throws Error naming `path` for a CRS that cannot be placed.
    GeoreferencedMap(const Georeference& crs, int64_t width, int64_t height, const std::string& path);

    // The position of `p` in pixel-centre coordinates ((0, 0) is the centre of the first pixel)
    // when it lies on the map's pixels (their outer edges included); false otherwise.
    bool pixelOf(const GeodeticPoint& p, double& col, double& row) const;
    // The geodetic point at PixelIsArea coordinates ((0, 0) the first pixel's top-left corner,
    // (0.5, 0.5) its centre), and back: the point's PixelIsArea coordinates wherever it lies
    // (false only where the projection has none). For resampling onto this map's grid.
    GeodeticPoint geodeticOf(double cornerCol, double cornerRow) const;
    bool cornerPixelOf(const GeodeticPoint& p, double& cornerCol, double& cornerRow) const;
    // A geographic box that holds every pixel (west may be below -180 or east above 180): points
    // outside it are not projected, so a projection's far side never lands on the map.
    const GeoExtent& bounds() const { return bounds_; }
    // The side of a pixel in metres on the CRS's ellipsoid (sqrt of the pixel's area).
    double metresPerPixel() const { return metresPerPixel_; }

private:
    bool crsOf(double latitude, double longitude, double& x, double& y) const;

    Georeference crs_;
    int64_t width_, height_;
    std::unique_ptr<MapProjection> projection_; // null: geographic
    std::array<double, 6> crsToPixel_{};
    double referenceLongitude_ = 0.0; // geographic: longitudes taken within 180 degrees of it
    GeoExtent bounds_;
    double metresPerPixel_ = 0.0;
};

struct MapPlacement {
    MapPlacement() = default;
    MapPlacement(const GeoExtent& e) : extent(e) {} // a plate carree over e, without georeferencing
    // The plate carree's extent; for a GeoreferencedMap, its bounds (for reports).
    GeoExtent extent;
    std::shared_ptr<const GeoreferencedMap> map; // null: a plate carree over `extent`
    std::string crs; // the file's CRS ("EPSG:4326 (WGS 84)"); empty without georeferencing
    // Pixels the map would have around the equator at its resolution (width * 360 / (east -
    // west) for a plate carree): what a face's default finest level is measured against.
    double columnsAround = 0.0;
};

// The placement of `info`'s map (the file `path`) given the --extent the user gave, if any.
// Throws OptionError("extent", ...) when the extent contradicts the file's georeferencing, and
// Error(path, ...) when the georeferencing cannot be used. `body` turns metres into degrees of
// the equator for columnsAround.
MapPlacement placeMap(const RasterInfo& info, const std::string& path, const std::optional<GeoExtent>& extent,
                      const PlanetBody& body);

} // namespace pyramid
