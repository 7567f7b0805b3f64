// The small DEM pyramid the readers' tests build of a raster (to compare two files' samples and
// placements through their pyramids): 32-sample tiles from a root of 8, levels 0..3.
#pragma once
#include "libpyramid/encode/dem/dem_encoder.hpp"

namespace pyramid::test {

inline DemEncodeOptions smallDemOptions() {
    DemEncodeOptions o;
    o.tileSize = 32;
    o.rootTileSize = 8;
    o.maxLevel = 3;
    return o;
}

} // namespace pyramid::test
