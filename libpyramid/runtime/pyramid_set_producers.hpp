// The runtime's producers over a region set (formats/pyramid_set.hpp): a main pyramid file and
// the region files its index lists, named by the main file, the index or their directory. Each
// tile is served by the deepest file that holds it (region_lookup.hpp). A path naming a file
// alone (no index beside it) opens that file exactly as the single-file producers do.
#pragma once
#include <memory>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/pyramid_set.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/runtime/height_query.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"
#include "libpyramid/runtime/residual_producer.hpp"

namespace pyramid {

// The deepest absolute level any file of the set holds (the main file's maxLevel for a file
// alone). Reads the files' headers.
int setMaxLevel(const PyramidSet& set);

// Producers over a checked set (openPyramidSet). Throw Error naming the set when it holds the
// other kind of pyramid.
std::shared_ptr<ResidualProducer> openResidualSet(const PyramidSet& set, const ResidualProducerOptions& options = {});
std::shared_ptr<ResidualProducer> openResidualSet(const std::string& path, const ResidualProducerOptions& options = {});
std::shared_ptr<OrthoProducer> openOrthoSet(const PyramidSet& set);
std::shared_ptr<OrthoProducer> openOrthoSet(const std::string& path);
// Elevation tiles of options.tileSize samples (0: the residual tile size) over a residual set:
// the residual producer's delta follows from the main file (elevationDelta).
std::shared_ptr<ElevationProducer> openElevationSet(const std::string& path, const ElevationProducerOptions& options = {});
// The residual producer such elevation tiles of n intervals (0: the residual tile size) need,
// for the GL producers (which take their residuals from the CPU).
std::shared_ptr<ResidualProducer> openResidualsForElevations(const std::string& path, int n);

// makeFileLevelProducer over a set: `level` is an absolute level, 0 .. setMaxLevel(set).
FileLevelProducer makeSetLevelProducer(const PyramidSet& set, int level, size_t cacheCapacity = 64);
FileLevelProducer makeSetLevelProducer(const std::string& path, int level, size_t cacheCapacity = 64);

// The file of a residual set that serves absolute tile (level, tx, ty): the deepest one holding
// it, and the tile's stored residuals there (tileSamples^2 int16, row 0 = bottom). Throws Error
// naming the set when no file holds the tile.
struct StoredResidualTile {
    std::string file;
    int level = 0, tx = 0, ty = 0; // in that file
    int side = 0;
    std::vector<int16_t> residuals;
};
StoredResidualTile storedResidualTile(const PyramidSet& set, int level, int tx, int ty);
// True when a file of the residual set holds absolute tile (level, tx, ty) (headers only).
bool residualSetHolds(const PyramidSet& set, int level, int tx, int ty);

// fileHeightAt over a set: the height at (u, v) at the deepest level a file of the set holds the
// point's tile at (the set's deepest level where the set is dense; a sparse set's where it is not).
PointHeight setHeightAt(const std::string& path, double u, double v);

} // namespace pyramid
