// The elevation producer on the GPU: the CPU ElevationProducer's tiles (zf, zc, zm), computed by
// a compute shader into RGBA32F textures (zf, zc, zm, 0), bit for bit equal to the CPU producer's
// (doc/format.md, "Elevation arithmetic" and "Coarse elevations"). The residuals still come
// from the CPU ResidualProducer (file reading and TIFF decoding).
//
// Not thread-safe: use it on the thread where its EglContext is current, which must stay alive
// (and current) as long as the producer and any tile it handed out.
#pragma once
#include <memory>
#include <vector>

#include "libpyramid/runtime/elevation_producer.hpp"
#include "libpyramid/gl/gl_objects.hpp"
#include "libpyramid/runtime/residual_producer.hpp"

namespace pyramid {

struct GlElevationTile {
    int level = 0, tx = 0, ty = 0;
    int size = 0;      // n + 5 texels per side
    GlTexture texture; // RGBA32F (zf, zc, zm, 0), row 0 = bottom
};

// A texture read back: its channels zf, zc and zm, to compare with the CPU producer's tiles.
struct GlElevationTexels {
    int level = 0, tx = 0, ty = 0;
    int size = 0;
    std::vector<float> zf, zc, zm;
};

class GlElevationProducer {
public:
    // Same contract and options as ElevationProducer; the cache holds GPU textures.
    GlElevationProducer(std::shared_ptr<const ResidualProducer> residuals, const ElevationProducerOptions& options);
    ~GlElevationProducer();

    int tileSize() const; // n
    int gridSize() const; // the render grid of zc
    int maxLevel() const;
    const std::string& path() const; // the residual file, for messages
    std::shared_ptr<const GlElevationTile> tile(int level, int tx, int ty);

    // The tile's texture read back.
    static GlElevationTexels read(const GlElevationTile& tile);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
