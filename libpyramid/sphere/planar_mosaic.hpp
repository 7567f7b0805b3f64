// The inputs of a planar tool opened as one raster: a file, files on one grid read as one
// (input/raster_mosaic.hpp), or groups of files on different grids (other CRSs, other
// resolutions) resampled onto one:
//
// * The CRS: --crs (PlanarTarget::crs), else the first input's (in priority order).
// * The grid: the finest input's resolution. When the finest group is in that CRS, its grid
//   (pixel size and alignment) extended; otherwise square pixels as long as the shorter ground
//   side of the finest group's pixels at its centre (in metres, or in degrees of latitude for a
//   geographic CRS), their edges on whole multiples of the pixel size in CRS units.
// * The extent: --extent (PlanarTarget::extent, in the CRS's units), else the union of every
//   group's footprint; widened to whole pixels.
// * Where the finest group is on the grid, it and every other group on that grid (files that
//   groupByGrid keeps apart for their sample type or nodata value) give their own samples as
//   they are (no resampling), the first listed with a value first; elsewhere the groups give
//   one, finest first, each sampled bilinearly at the pixel's centre (its geodetic point,
//   forward-projected into the group's CRS: sphere/map_mosaic.hpp). Pixels no group reaches
//   are nodata (the finest group's declared value, else NaN; colours 0).
// * Geodetic coordinates of every CRS are taken on the target CRS's ellipsoid (no datum shift).
// * North-up: a file whose axis-aligned transform runs its rows north (south-up) or its columns
//   west is read mirrored, sample for sample, under the transform of the same ground, so that
//   rows run south and columns east as the planar pyramids and their sidecars take them.
//
// One file, or files on one grid, without --crs or --extent are read as they are (north-up).
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "libpyramid/input/raster_source.hpp"

namespace pyramid {

// Where a planar mosaic is put: which CRS, which ground rectangle.
struct PlanarTarget {
    std::string crs;                              // "EPSG:N"; empty: the first input's CRS
    std::optional<std::array<double, 4>> extent;  // min x, min y, max x, max y in the CRS's units
    bool empty() const { return crs.empty() && !extent; }

    // "MINX,MINY,MAXX,MAXY" in the CRS's units; throws OptionError("extent", ...) otherwise.
    static std::array<double, 4> parseExtent(const std::string& text);
};

// `inputs` in priority order. Throws Error naming a file that is missing, has no usable
// georeferencing (when there are several, or a target is given), or a CRS that cannot be placed;
// with `sameSamples` (imagery, whose colours are not numbers to convert), a file whose band
// count or sample type differs from the first's; OptionError("crs" or "extent", ...) for a
// target that cannot be used.
std::unique_ptr<RasterSource> openPlanarMosaic(const std::vector<std::string>& inputs, int cacheMegabytes,
                                               bool sameSamples = false, const PlanarTarget& target = {});

} // namespace pyramid
