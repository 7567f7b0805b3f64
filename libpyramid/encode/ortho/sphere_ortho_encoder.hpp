// The ortho pyramids of a spherical planet: one equirectangular image in, the six cube faces out
// (cube_faces.hpp), each a complete set of ortho files as encodeOrtho writes them, named
// NAME1.dat .. NAME6.dat after their face (RGB1.dat ...; proland-compat, "Spherical (cube)
// variants"). Each face's finest level samples the image at the geodetic point of every pixel
// (ortho_levels.hpp, "Cube faces"), and its tile borders are its neighbours' pixels, so that the
// faces join without seams at every level.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/face_sampler.hpp"
#include "libpyramid/sphere/map_sources.hpp"

namespace pyramid {

struct SphericalOrthoOptions {
    // ortho.name "RGB" gives RGB1.dat .. RGB6.dat; ortho.levels.maxLevel counts per face (none: the
    // smallest level at least width / 4 pixels wide); ortho.levels.stretch is not used;
    // ortho.progress counts the tiles of all faces together.
    OrthoEncodeOptions ortho;
    // Of an image without georeferencing (default: the globe). A georeferenced input places
    // itself (sphere/map_placement.hpp): an extent then may only repeat a geographic file's own.
    std::optional<GeoExtent> extent;
    std::string body = "wgs84";   // PlanetBody::parse
    std::vector<int> faces{1, 2, 3, 4, 5, 6};
    // Called, before any face is encoded, with each of the inputs' warnings (MapSources).
    std::function<void(const std::string&)> warning;
};

struct SphericalOrthoFaceReport {
    int face = 0;
    OrthoReport ortho;
    std::vector<GroundSampleDistance> gsd; // per level: distance between neighbouring pixels, metres
};

struct SphericalOrthoReport {
    std::string input;               // the input, or the first of several and how many more
    std::vector<std::string> inputs; // every file read, in priority order
    std::string directory;
    std::string body; // PlanetBody::describe()
    GeoExtent extent; // the image's (a projected one: a geographic box around it)
    std::string crs;  // the input's CRS, if georeferenced
    std::vector<SphericalOrthoFaceReport> faces;
    std::vector<std::string> warnings; // MapSources::warnings, also given to options.warning
    int threads = 0;
    double seconds = 0.0;
};

// The map of a spherical ortho build, opened as preprocessSphericalOrtho opens it: `inputs` (one
// file or a mosaic: map_sources.hpp), every file of the first one's bands and sample type (else
// Error naming the file), the first `channelsOf(first file's info)` channels read.
struct OrthoMap {
    MapSources sources;
    std::unique_ptr<RasterSource> described; // several grids: the first file, which describes the map
    // The raster the faces' levels describe the map by, and the map to sample when there are
    // several grids (else null: the raster is sampled).
    const RasterSource& source() const { return sources.source ? *sources.source : *described; }
    const GeodeticMap* map() const { return sources.source ? nullptr : sources.map.get(); }
};
OrthoMap openOrthoMap(const std::vector<std::string>& inputs, const std::optional<GeoExtent>& extent,
                      const PlanetBody& body, int cacheMegabytes,
                      const std::function<int(const RasterInfo&)>& channelsOf);

// Encodes the faces one after the other (each with every thread). Throws Error naming the file
// or option at fault; options are checked before any file is written, and each face's files
// appear whole or not at all.
SphericalOrthoReport encodeSphericalOrtho(const std::string& input, const std::string& directory,
                                          const SphericalOrthoOptions& options);
// A mosaic of georeferenced images, in priority order: files on one grid read as one raster,
// several grids each placed by its own georeferencing, the finest giving a pixel its colour
// where they overlap (sphere/map_sources.hpp). They must share the band count and sample type.
SphericalOrthoReport encodeSphericalOrtho(const std::vector<std::string>& inputs, const std::string& directory,
                                          const SphericalOrthoOptions& options);
// A map already set up: a caller's own (sources.map, e.g. a procedural planet, values 0..255 for
// an 8-bit description), described by sources.source (a raster of the map's size, channels and
// sample type, never read) and sources.placement.
SphericalOrthoReport encodeSphericalOrtho(const MapSources& sources, const std::string& directory,
                                          const SphericalOrthoOptions& options);

nlohmann::json toJson(const SphericalOrthoReport& report);

} // namespace pyramid
