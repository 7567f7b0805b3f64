// The CPU normal producer: the normals of the elevation producer's tiles (the seeds' normal
// producer), planar or on a sphere, with the coarse normals of the parent's render mesh for
// geomorphing (filters/terrain_normals.hpp; doc/shading.md). Produced tiles are kept in an LRU
// cache of bounded capacity. Thread-safe.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/filters/terrain_normals.hpp"
#include "libpyramid/runtime/elevation_producer.hpp"

namespace pyramid {

struct NormalTile {
    int level = 0, tx = 0, ty = 0;
    int size = 0;               // n + 1 vertices a side (no border)
    std::vector<float> normals; // size^2 x (nx, ny, ncx, ncy), row 0 = south
};

struct NormalProducerOptions {
    Deformation deformation = Deformation::Plane;
    // Plane: the root quad's side in height units (the samples of level L are size / (2^L n)
    // apart). Sphere: the radius in height units; the root quad is the cube face [-R, R]^2.
    double size = 0.0;
    size_t cacheCapacity = 256;
};

// Throws Error naming `where` (the elevations' file) when options.size is not a positive finite
// number: the CPU and GL producers' one check.
void checkNormalOptions(const NormalProducerOptions& options, const std::string& where);

class NormalProducer {
public:
    // Throws Error (naming the elevations' file) when options.size is not a positive finite number.
    NormalProducer(std::shared_ptr<ElevationProducer> elevations, const NormalProducerOptions& options);
    ~NormalProducer();

    int tileSize() const; // n: tiles hold (n + 1)^2 normals
    const NormalProducerOptions& options() const;
    // Tile (level, tx, ty), from elevation tiles (level, tx, ty) and its parent's.
    std::shared_ptr<const NormalTile> tile(int level, int tx, int ty);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
