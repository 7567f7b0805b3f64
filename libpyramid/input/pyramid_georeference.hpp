// Where a planar pyramid lies in its input's CRS: what preprocessDem's and preprocessOrtho's
// reports say of a georeferenced input (their `georeference` object) and what the sidecar file
// beside the output holds, so that a GIS or an engine can put the tiles back on the ground.
//
// The pyramid's root quad covers a rectangle of the input's pixels (PixelIsArea coordinates,
// georeference.hpp): the affine pixel-to-CRS transform carries it, and every level's sample
// spacing, into CRS units. No resampling of the CRS happens here; the planar encoders are not
// changed by georeferencing.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/atomic_file.hpp"
#include "formats/georeference_sidecar.hpp"
#include "libpyramid/input/georeference.hpp"

namespace pyramid {

struct PyramidGeoreference {
    Georeference crs;
    std::string samples;               // "vertices" (DEM) or "pixel centres" (ortho)
    // Root quad: the CRS positions of its north-west and south-east corners' samples for DEM
    // vertices, of its outer pixel edges for ortho pixels; also min/max boxes below.
    std::array<double, 4> rootExtent{}; // min x, min y, max x, max y (CRS units; geographic: lon, lat)
    std::array<double, 4> dataExtent{}; // the input's pixels, outer edges
    // Per level (0 = root): CRS units between neighbouring samples along the columns (x) and the rows (y).
    std::vector<std::array<double, 2>> unitsPerSample;
};

// `root`: the root quad in the input's PixelIsArea pixel coordinates, {col0, row0, col1, row1}
// (north-west, south-east); `cellsPerLevel[l]`: samples spacings across the root quad at level l
// (intervals for DEM vertices, pixels for ortho).
PyramidGeoreference georeferencePyramid(const Georeference& crs, int width, int height, const std::array<double, 4>& root,
                                        const std::vector<int64_t>& cellsPerLevel, const std::string& samples);

nlohmann::json toJson(const PyramidGeoreference& g);

// The unit a raster's heights are stored in and what reading them multiplied them by, for
// reports and sidecars: {"unit", "unit_metres", "from", "scaled_by"}; null when its GeoKeys name
// no unit (the heights are as stored).
nlohmann::json heightUnitJson(const Georeference& g);

// Writes toJson(g) (and the pyramid file's name) to `sidecar` atomically (formats/atomic_file.hpp).
void writeGeoreferenceSidecar(const std::string& sidecar, const std::string& pyramid, const PyramidGeoreference& g);
// The sidecar's text for the pyramid file `pyramid` (its name is recorded).
std::string georeferenceSidecarText(const std::string& pyramid, const PyramidGeoreference& g);

// The ground distance between the samples of `level` of the pyramid `main` along x and y, in
// metres, from its sidecar (georeferenceSidecarPath): CRS units times the unit's metres;
// geographic degrees at the root quad's middle latitude, on the CRS's ellipsoid. {0, 0} without
// a sidecar or without the level; throws Error naming the sidecar when it is not one.
std::array<double, 2> groundSpacing(const std::string& main, int level);

} // namespace pyramid
