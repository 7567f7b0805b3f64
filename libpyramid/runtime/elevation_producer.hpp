// The CPU elevation producer: upsample-and-add (doc/format.md, "Elevation arithmetic") from
// the parent elevation tile and the residual tile, for elevation tiles of n = tileSize / 2^k
// samples (+5) with the matching delta = minLevel - k, as the seeds' elevation producer does.
// Produced tiles are kept in an LRU cache of bounded capacity. Thread-safe.
#pragma once
#include <memory>
#include <vector>

#include "libpyramid/runtime/residual_producer.hpp"

namespace pyramid {

struct ElevationTile {
    int level = 0, tx = 0, ty = 0;
    int size = 0;          // n + 5 samples per side
    std::vector<float> zf; // size^2, row 0 = bottom: the upsample-and-add elevations
    std::vector<float> zc; // coarse elevations: linear interpolation of the parent's zm on the
                           // gridSize render grid (north-west to south-east diagonals)
    // The modified elevations: zf itself, as no layer modifies them (one array, not a copy).
    const std::vector<float>& zm() const { return zf; }
};

struct ElevationProducerOptions {
    int tileSize = 0;         // n, elevation samples per side without the +5; 0 = the residual tileSize
    int gridSize = 0;         // render grid quads per side for zc; 0 = n
    size_t cacheCapacity = 256; // tiles kept (LRU)
};

class ElevationProducer {
public:
    // `residuals` must have been built with delta = minLevel - log2(residual tileSize / n).
    ElevationProducer(std::shared_ptr<const ResidualProducer> residuals, const ElevationProducerOptions& options);
    ~ElevationProducer();

    int tileSize() const; // n
    int gridSize() const; // the render grid of zc
    int maxLevel() const; // deepest level with residuals
    // Whether tile (level, tx, ty) has residuals of its own (ResidualProducer::hasTile): false
    // beyond every file, where a sparse set (doc/format.md 1.5) has no more resolution.
    bool hasResiduals(int level, int tx, int ty) const;
    const std::string& path() const; // the residual file, for messages
    std::shared_ptr<const ElevationTile> tile(int level, int tx, int ty);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Elevation tiles that coincide with the tiles of one file level, to rebuild a file tile by
// tile: n = the file's tile intervals at `fileLevel`, delta = min(fileLevel, minLevel), and file
// tile (fileLevel, tx, ty) is producer tile (fileLevel - delta, tx, ty).
struct FileLevelProducer {
    std::shared_ptr<ElevationProducer> producer;
    int delta = 0;
    int n = 0;
    std::shared_ptr<const ElevationTile> fileTile(int fileLevel, int tx, int ty) const {
        return producer->tile(fileLevel - delta, tx, ty);
    }
};
FileLevelProducer makeFileLevelProducer(const std::string& file, int fileLevel, size_t cacheCapacity = 64);

// delta = minLevel - k for elevation tiles of n = tileSize / 2^k; throws Error (naming `where`,
// e.g. the file) if n does not divide tileSize by a power of two no larger than 2^minLevel.
int elevationDelta(const ResidualHeader& header, int n, const std::string& where = "");

// The elevation tiling that a residual producer and options give, checked once for the CPU and
// GL producers alike: n, k = log2(tileSize / n) and the render grid of zc. Throws Error naming
// the residual file when the producer's delta does not match n or gridSize does not divide n.
struct ElevationTiling {
    int n = 0;
    int k = 0;
    int gridSize = 0;
};
ElevationTiling elevationTiling(const ResidualProducer& residuals, const ElevationProducerOptions& options);

} // namespace pyramid
