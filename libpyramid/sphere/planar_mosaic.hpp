// The inputs of a planar tool opened as one raster: a file, files on one grid read as one
// (input/raster_mosaic.hpp), or groups of files on different grids (other CRSs, other
// resolutions) resampled onto one:
//
// * The grid is the finest group's (the first listed among equally fine ones): its CRS, pixel
//   size and alignment, extended to the union of every group's footprint there.
// * Where the finest group has a value, its own sample is taken as it is (no resampling); elsewhere
//   the other groups give one, finest first, each sampled bilinearly at the pixel's centre
//   (its geodetic point, forward-projected into the group's CRS: sphere/map_mosaic.hpp).
//   Pixels no group reaches are nodata (the finest group's declared value, else NaN; colours 0).
// * Geodetic coordinates of every CRS are taken on the finest group's ellipsoid (no datum shift).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/input/raster_source.hpp"

namespace pyramid {

// `inputs` in priority order. Throws Error naming a file that is missing, has no usable
// georeferencing (when there are several), or a CRS that cannot be placed; with
// `sameSamples` (imagery, whose colours are not numbers to convert), a file whose band count or
// sample type differs from the first's.
std::unique_ptr<RasterSource> openPlanarMosaic(const std::vector<std::string>& inputs, int cacheMegabytes,
                                               bool sameSamples = false);

} // namespace pyramid
