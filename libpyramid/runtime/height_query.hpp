// Heights at points, as the runtime rebuilds them: a pipeline's check that a build landed
// where it should (`pyramid height`, pyramid_elevation_height). The height at a point is the
// bilinear interpolation, in double precision, of the four samples around it in the tile of
// the chosen level that holds it (level_heights.hpp: the order of the arithmetic): the tile's
// own float32 elevations (zf), exactly as the producer rebuilds them from the file.
#pragma once
#include <array>
#include <string>

#include "libpyramid/runtime/elevation_producer.hpp"

namespace pyramid {

struct PointHeight {
    double height = 0.0;
    int level = 0, tx = 0, ty = 0; // the producer's tile that held the point
    double x = 0.0, y = 0.0;       // the point in that level's sample intervals, from the south-west
};

// The height at (u, v), the fraction of the root quad east and north of its south-west corner
// (both in [0, 1]), in `producer`'s tiles of `level` (-1: the deepest whose tile holding the
// point has residuals; where a sparse set has no more resolution, the deepest file holding the
// point). Throws Error for a
// point outside the quad or a level it does not have.
PointHeight heightAt(ElevationProducer& producer, double u, double v, int level = -1);

// The same at the finest level of the residual file `file`, with elevation tiles that coincide
// with the file's own tiles.
PointHeight fileHeightAt(const std::string& file, double u, double v);

// The root quad's (u, v) of the point (x, y) in the CRS of the input a planar file was built
// from (with `geographic`, which a geographic CRS requires: longitude and latitude in degrees
// from Greenwich, turned into the CRS's units from its prime meridian), placed by the sidecar
// written beside the file (input/pyramid_georeference.hpp). Throws Error when the file has no
// sidecar, its CRS is not geographic when required, or its input was rotated off north-up.
std::array<double, 2> crsToRootQuad(const std::string& file, double x, double y, bool geographic);

} // namespace pyramid
