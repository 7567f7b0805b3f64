// preprocessSphericalDem as a library call: a global (or partial) equirectangular elevation map
// in, six residual pyramids out, one per cube face (DIR/DEM1.dat .. DIR/DEM6.dat), numbered,
// oriented and projected as the original Proland tools do, with the body's geodesy
// (doc/spherical.md). Each face is a planar pyramid of the residual encoder whose tile borders
// are the neighbouring faces' samples.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/encode/dem/dem_encoder.hpp"
#include "libpyramid/encode/residual/height_source.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/face_sampler.hpp"
#include "libpyramid/sphere/map_sources.hpp"

namespace pyramid {

// The columns around the equator past which a map needs face level `level` of a pyramid whose
// root tile has `rootIntervals` intervals: a face spans a quarter of the equator, so a map of C
// columns is matched by the smallest level L with rootIntervals << L >= C / 4 (the default
// maxLevel), and needs level L when C > 4 x (rootIntervals << (L - 1)). 0 for level 0.
double columnsNeedingLevel(int64_t rootIntervals, int level);

// The heights of one face's vertex grid, borders beyond the face included (the encoder's
// source, and what `verifySphericalDem` compares with).
class FaceHeights final : public HeightSource {
public:
    // With `rootIntervals` (the face pyramid's root tile), the heights of each level are the map's
    // members that need that level or a deeper one (columnsNeedingLevel): a fine inset's heights
    // go down to its own level, a coarse base's to its own; 0: every member at every level.
    explicit FaceHeights(const FaceSampler& sampler, int64_t rootIntervals = 0)
        : sampler_(sampler), rootIntervals_(rootIntervals) {}
    void sample(SourceGrid& grid) const override;
    bool mayHaveHeights(int64_t x0, int64_t y0, int64_t x1, int64_t y1) const override;
    bool mayHaveHeightsAt(int level, int64_t x0, int64_t y0, int64_t x1, int64_t y1) const override;
    bool severalLevels() const override { return rootIntervals_ > 0 && sampler_.severalResolutions(); }

private:
    const FaceSampler& sampler_;
    int64_t rootIntervals_ = 0;
};

struct SphericalDemOptions {
    // Tile sizes, scale, band, nodata, threads, cache. dem.maxLevel counts per face (-1: the
    // smallest face pyramid at least as fine as the map at the equator, i.e. rootTileSize <<
    // maxLevel >= width / 4); dem.stretch does not apply; dem.progress sees the tiles of every
    // face, dem.reconstruction is not called (see `reconstruction` below).
    DemEncodeOptions dem;
    // Of a map without georeferencing (default: the globe). A georeferenced input places itself
    // (sphere/map_placement.hpp): an extent then may only repeat a geographic file's own.
    std::optional<GeoExtent> extent;
    std::string body = "wgs84";   // PlanetBody::parse
    double heightScale = 1.0;     // height = sample value x heightScale (e.g. 10000/255)
    // The height of the root's nodata (beyond the map, or its holes), in the pyramid's height
    // units, e.g. 0 for sea level; none: filled smoothly from the map's heights, across the cube
    // (encode/dem/sphere_root_fill.hpp). Deeper levels predict either from the root.
    std::optional<double> fillHeight;
    std::string name = "DEM";     // files NAME1.dat .. NAME6.dat
    std::vector<int> faces{1, 2, 3, 4, 5, 6};
    // Called, before any face is encoded, with each of the inputs' warnings (MapSources).
    std::function<void(const std::string&)> warning;
    // Called from one thread at a time with each tile's reconstruction: for tests.
    std::function<void(int face, int level, int tx, int ty, const std::vector<float>&)> reconstruction;
};

struct SphericalDemFaceReport {
    int face = 0;
    DemReport dem;                          // the face's file, levels and errors
    std::vector<GroundSampleDistance> gsd;  // per level, metres between neighbouring samples
};

struct SphericalDemReport {
    std::string input;               // the input, or the first of several and how many more
    std::vector<std::string> inputs; // every file read, in priority order
    std::string directory;
    RasterInfo inputInfo;
    int band = 0;                 // 0-based
    std::optional<double> nodata; // used, if any
    double heightScale = 1.0;
    std::optional<double> fillHeight; // SphericalDemOptions::fillHeight
    std::string body;             // PlanetBody::describe()
    GeoExtent extent;             // the map's (a projected map: a geographic box around it)
    std::string crs;              // the input's CRS, if georeferenced
    std::vector<SphericalDemFaceReport> faces;
    std::vector<std::string> warnings; // MapSources::warnings, also given to options.warning
    int threads = 0;
    double seconds = 0.0;
};

// Writes every face into `directory` (created if missing); the files appear together at the
// end, or not at all when a face fails. Throws Error with a one-line message on bad input,
// impossible options or int16 overflow.
SphericalDemReport encodeSphericalDem(const std::string& input, const std::string& directory,
                                      const SphericalDemOptions& options);
// A mosaic of georeferenced files, in priority order: files on one grid are read as one raster
// (input/raster_mosaic.hpp), several grids are each placed by their own georeferencing, the
// finest giving a point its height where they overlap (sphere/map_mosaic.hpp). One file is
// encodeSphericalDem(file).
SphericalDemReport encodeSphericalDem(const std::vector<std::string>& inputs, const std::string& directory,
                                      const SphericalDemOptions& options);
// A map already set up: a caller's own (sources.map, e.g. a procedural planet), described by
// sources.name, info (its width sets the default maxLevel) and placement (extent, CRS, columns
// around the equator); sources.source may be null, and options.dem.band and nodata do not apply.
SphericalDemReport encodeSphericalDem(const MapSources& sources, const std::string& directory,
                                      const SphericalDemOptions& options);

nlohmann::json toJson(const SphericalDemReport& report);

} // namespace pyramid
