// The inputs of a spherical tool opened as one planet's map: a file, files on one grid read as
// one raster (input/raster_mosaic.hpp), or several grids each placed by its own
// georeferencing (map_mosaic.hpp). The one place that decides which, for the DEM and ortho
// tools alike.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

struct MapSources {
    std::string name;               // the input, or "FIRST and N more"
    RasterInfo info;                // the raster's; of several grids, the finest one's
    MapPlacement placement;         // of several grids: their union's box, their CRSs, the finest resolution
    std::optional<double> nodata;   // the raster's (of several grids: each has its own)
    std::unique_ptr<RasterSource> source; // the raster; null for several grids
    std::unique_ptr<GeodeticMap> map;     // channels [c0, c1), read as `read`
    // What the user may not have meant, one line each: a map without georeferencing whose pixels
    // its extent (the globe, by default) makes far from square.
    std::vector<std::string> warnings;

    // Gives each warning to `warning`, when set.
    void tell(const std::function<void(const std::string&)>& warning) const {
        for (const std::string& w : warnings) {
            if (warning) {
                warning(w);
            }
        }
    }
};

// `inputs` in priority order (first listed first where files of one resolution overlap).
// `extent` places a raster without georeferencing (map_placement.hpp); several files must be
// georeferenced, and then take no extent (OptionError("extent")). `nodataOf(info, name)` gives a
// raster's nodata value and checks what the tool needs of it (may throw).
MapSources openMapSources(const std::vector<std::string>& inputs, const std::optional<GeoExtent>& extent,
                          const PlanetBody& body, int cacheMegabytes, SampleRead read, int c0, int c1,
                          const std::function<std::optional<double>(const RasterInfo&, const std::string&)>& nodataOf);

// A map computed at points over the whole globe (a caller's planet, a derived quantity such as
// terrain aperture): `map`, described as a raster of `resolution` x resolution/2 samples of
// `channels` (1..4) of `type` (`source`), which the spherical encoders size their faces by and
// never read. Throws Error naming `name` for channels out of 1..4 or a resolution below 4.
MapSources globalMapSources(const std::string& name, std::unique_ptr<GeodeticMap> map, int channels, int resolution,
                            SampleType type);

} // namespace pyramid
