// Rasters cut from one for the mosaic tests: a geographic grid, the height of each of its pixels,
// and georeferenced windows of it written as GeoTIFFs.
#pragma once
#include <string>

#include "tests/support/paths.hpp"

namespace pyramid::test {

// A geographic raster of `step`-degree pixels with its first pixel's corner at (west, north).
struct Grid {
    double west, north, step;
};

// The height of pixel (x, y) of the raster the cuts are taken from: a slope with a little texture.
float heightAt(int x, int y);

// Pixels [x0, x0 + w) x [y0, y0 + h) of the raster whose pixel (x, y) holds heightAt(x, y), on
// grid `g`, written as the GeoTIFF `name` in `dir` (EPSG:4326); returns its path.
std::string cut(const TempDir& dir, const std::string& name, const Grid& g, int x0, int y0, int w, int h);

} // namespace pyramid::test
