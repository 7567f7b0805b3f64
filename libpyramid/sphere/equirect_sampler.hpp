// Sampling a planet's map by geodetic latitude and longitude: an equirectangular (plate carree)
// raster, described below, or a georeferenced one whose pixel a point finds through its CRS
// (GeoreferencedMap, map_placement.hpp; then there is no wrapping and the map's own pixel edges
// bound it, with the same interpolation, clamping and nodata rules).
//
// The raster covers the extent [west, east] x [south, north] in degrees (default: the whole
// globe), column 0 on the west, row 0 on the north. Samples are PIXEL CENTRES (area
// convention): pixel (i, j) covers longitudes west + [i, i + 1] * (east - west) / W and its
// value is that of its centre, latitude north - (j + 0.5) * (north - south) / H. A global map
// of W x H pixels thus has its first column centred half a pixel east of -180 degrees. (A
// grid-registered map, whose first and last columns both sit on +-180, is described by an
// extent half a pixel wider on every side.)
//
// Values between pixel centres are interpolated bilinearly. A global extent (east - west = 360)
// wraps around in longitude; between the last row of pixel centres and the pole (or the edge of
// a partial extent) the nearest row is used (clamped), as is the nearest column at the west and
// east edges of a partial extent. Points outside the extent have no value (nodata), as does a
// point whose interpolation would use a nodata pixel with a non-zero weight. Colours (read as
// SampleRead::UInt16) are judged by the whole pixel, every channel of the file read whatever
// channels are sampled: no value where alpha is 0 or every channel is nodata
// (input/colour_coverage.hpp).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <memory>

#include "libpyramid/sphere/planet_body.hpp"
#include "libpyramid/input/raster_source.hpp"

namespace pyramid {

struct GeoExtent {
    double west = -180.0, south = -90.0, east = 180.0, north = 90.0; // degrees
    // "WEST,SOUTH,EAST,NORTH" in degrees, an extent as validate() wants it. Throws
    // OptionError("extent", ...) otherwise.
    static GeoExtent parse(const std::string& text);
    // west < east <= west + 360 (within -540..540), -90 <= south < north <= 90. Throws
    // OptionError("extent", ...) otherwise.
    void validate() const;
    // The rule of validate() this extent breaks, or nullptr.
    const char* brokenRule() const;
    bool global() const { return east - west >= 360.0; }
};

// How raster values are read: as numbers (readFloat), or as plain integers widened to uint16
// (readUInt16: 8-bit 0..255, 16-bit 0..65535), for colours.
enum class SampleRead { Float, UInt16 };

class GeoreferencedMap;
struct FaceGrid;
struct MapPlacement;

// A planet's map as the face samplers see it: values at geodetic points. One raster
// (EquirectSampler, below) or several, each placed by its own georeferencing (map_mosaic.hpp).
class GeodeticMap {
public:
    virtual ~GeodeticMap() = default;
    virtual int channels() const = 0;
    // A geographic box holding every point that has a value (reports, coverage).
    virtual const GeoExtent& extent() const = 0;
    // True when every point may have a value (the coverage test is not worth making).
    virtual bool everywhere() const { return extent().global(); }
    // False only when no point of the box [south, north] x [west, east] (degrees, longitudes
    // unwrapped: west may be below -180, east above 180; every longitude when `allLongitudes`)
    // can have a value. By default, whether the box meets extent().
    virtual bool mayCover(double south, double north, double west, double east, bool allLongitudes) const;
    // The same for the values of the map's members at least `columnsAround` pixels around the
    // equator fine (MapPlacement::columnsAround): a map of one resolution is one member, and
    // every level of a pyramid made from it is its level or coarser (the default: mayCover). A
    // mosaic of several resolutions (map_mosaic.hpp) answers for its finer members alone.
    // Whether the map's parts have several resolutions (mayCoverFinerThan may then answer false
    // where mayCover does not). False by default.
    virtual bool severalResolutions() const { return false; }
    virtual bool mayCoverFinerThan(double columnsAround, double south, double north, double west, double east,
                                   bool allLongitudes) const {
        (void)columnsAround;
        return mayCover(south, north, west, east, allLongitudes);
    }
    // mayCoverFinerThan for face samples [x0, x1] x [y0, y1] of `grid` on cube face `face`, by a
    // map that knows its coverage face by face (an aperture over a planet's faces); nullopt (the
    // default): not known so, the samples' geographic box is asked.
    virtual std::optional<bool> mayCoverFaceFinerThan(double columnsAround, int face, const FaceGrid& grid, int64_t x0,
                                                      int64_t y0, int64_t x1, int64_t y1) const {
        (void)columnsAround, (void)face, (void)grid, (void)x0, (void)y0, (void)x1, (void)y1;
        return std::nullopt;
    }
    // Samples `count` points. out: count * channels() values, interleaved; valid: count flags
    // (1 = a value, 0 = none; out is 0 there). Thread-safe.
    virtual void sample(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const = 0;
    // The same, the points being those of a grid of `columnsAround` pixels around the equator (a
    // face grid's samples: FaceSampler): a map whose values depend on the resolution they are
    // read at (an aperture searched at that level's spacing) answers for it. By default, sample().
    virtual void sampleFor(double columnsAround, const GeodeticPoint* points, size_t count, float* out,
                           uint8_t* valid) const {
        (void)columnsAround;
        sample(points, count, out, valid);
    }
};

class EquirectSampler final : public GeodeticMap {
public:
    // Channels [c0, c1) are sampled; `nodata` marks missing pixels (NaN allowed). Throws Error
    // naming the file for channels it does not have.
    EquirectSampler(const RasterSource& source, const GeoExtent& extent, int c0, int c1, SampleRead read,
                    std::optional<double> nodata);
    // The map placed by its georeferencing or extent (map_placement.hpp).
    EquirectSampler(const RasterSource& source, const MapPlacement& placement, int c0, int c1, SampleRead read,
                    std::optional<double> nodata);

    int channels() const override { return c1_ - c0_; }
    const GeoExtent& extent() const override { return extent_; }

    // Samples `count` points. out: count * channels() values, interleaved; valid: count flags
    // (1 = a value, 0 = nodata; out is 0 there). Reads one window around the points when it is
    // small, else a 2 x 2 window per point, so memory stays bounded by the number of points.
    // Thread-safe.
    void sample(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const override;

private:
    const RasterSource& source_;
    GeoExtent extent_;
    std::shared_ptr<const GeoreferencedMap> map_; // null: a plate carree over extent_
    bool wraps_ = false;                           // a global plate carree
    int c0_, c1_;
    SampleRead read_;
    std::optional<double> nodata_;
};

} // namespace pyramid
