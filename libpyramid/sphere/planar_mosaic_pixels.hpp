// The pixels of a planar mosaic (planar_mosaic.hpp), for openPlanarMosaic alone: the groups
// resampled onto one grid, and a file read north-up.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

// A group whose own samples the mosaic takes as they are, with its pixel (0, 0) in the mosaic.
struct OwnGroup {
    std::unique_ptr<RasterSource> source;
    int64_t x = 0, y = 0;
};

// The mosaic's pixels: `groups` (files by grid, in priority order) resampled onto the grid, `own`
// the groups on the grid (the finest group in the CRS and any other on its grid) that give their
// own samples as they are, in priority order; (x0, y0): the grid's pixel (0, 0) in the mosaic;
// `grid`: the CRS and transform of the grid's pixel coordinates (the mosaic's, shifted by (x0, y0)).
std::shared_ptr<const RasterPixels> resampledPixels(std::vector<std::vector<std::string>> groups,
                                                    std::vector<OwnGroup> own, int x0, int y0, RasterInfo info,
                                                    PlanetBody body, int cacheMegabytes, const Georeference& grid,
                                                    int64_t gridWidth, int64_t gridHeight, const std::string& gridName);

// The files of one grid as one raster (RasterSource::openMosaic), north-up: a planar pyramid's
// tiles put north at the top whatever way the file's rows run (a file whose axis-aligned
// transform runs its rows north or its columns west is read mirrored, sample for sample).
std::unique_ptr<RasterSource> openNorthUp(const std::vector<std::string>& group, int cacheMegabytes);

} // namespace pyramid
