// `pyramid verify DEM.dat --source INPUT`: every level of a residual file rebuilt with the CPU
// elevation producer and compared with the source heights, sampled by the same rule as
// preprocessDem (libpyramid/encode/dem/dem_sampling.hpp).
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/planar_mosaic.hpp"

namespace pyramid {

struct DemVerifyOptions {
    int band = 0;
    std::optional<double> nodata;
    bool ignoreDeclaredNodata = false;
    bool stretch = false;
    int threads = 0;
    PlanarTarget target; // as the pyramid was built (--crs, --extent)
    // (tiles compared, tiles in all), the latter the same on every call; one thread at a time.
    std::function<void(int64_t, int64_t)> progress;
};

struct DemVerifyLevel {
    int level = 0;
    int64_t tiles = 0;
    int64_t samples = 0;
    double maxError = 0.0;
    double rmsError = 0.0;
    int64_t beyondBound = 0; // samples whose error passes scale/2 (+ float32 rounding)
    // Samples whose rebuilt or source height is NaN or infinite: never within any bound, and
    // left out of maxError and rmsError so that those stay numbers.
    int64_t nonFinite = 0;
};

struct DemVerifyReport {
    std::string file;
    std::string source;
    double scale = 0.0;
    double bound = 0.0; // scale / 2
    std::vector<DemVerifyLevel> levels;
    // Every sample within the bound, and none non-finite.
    bool ok() const;
};

// `file` names a residual file, or a region set (its main file, index or directory:
// formats/pyramid_set.hpp), verified whole: each tile rebuilt from the deepest file holding it.
DemVerifyReport verifyDem(const std::string& file, const std::string& source, const DemVerifyOptions& options);
// Against a raster already open (a caller's own heights: RasterSource::fromPixels);
// options.target does not apply.
DemVerifyReport verifyDem(const std::string& file, const RasterSource& source, const DemVerifyOptions& options);

// The cube faces preprocessSphericalDem wrote into a directory, against the planet's map (a
// face's region set when its index, NAMEi.dat.regions.json, is beside it).
struct SphericalDemVerifyOptions {
    std::string body = "wgs84";  // as encoded (PlanetBody::parse)
    std::string name = "DEM";    // files NAME1.dat .. NAME6.dat
    std::vector<int> faces{1, 2, 3, 4, 5, 6};
    double heightScale = 1.0;    // as encoded
    std::string source = "map";  // names the map in the reports
    int threads = 0;
    // The map's files, read as preprocessSphericalDem read them (the overload taking inputs):
    int band = 0;                      // 0-based
    std::optional<double> nodata;      // overrides what the files declare
    bool ignoreDeclaredNodata = false;
    std::optional<GeoExtent> extent;   // places a map without georeferencing
    // (tiles compared, tiles of all the faces); one thread at a time.
    std::function<void(int64_t, int64_t)> progress;
};
// One report per face, in the order of options.faces.
std::vector<DemVerifyReport> verifySphericalDem(const std::string& directory, const GeodeticMap& map,
                                                const SphericalDemVerifyOptions& options);
// Against the map files the faces were built from (one, or a mosaic: sphere/map_sources.hpp),
// opened with the options' band, nodata and extent as preprocessSphericalDem opens them;
// options.source is the map's name.
std::vector<DemVerifyReport> verifySphericalDem(const std::string& directory, const std::vector<std::string>& inputs,
                                                const SphericalDemVerifyOptions& options);

nlohmann::json toJson(const DemVerifyReport& report);

} // namespace pyramid
