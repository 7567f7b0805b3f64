// The normal producer on the GPU: the CPU NormalProducer's tiles (nx, ny, ncx, ncy), computed by a
// compute shader from the GL elevation producer's tiles into RGBA32F textures, bit for bit equal
// to the CPU producer's on a GPU whose float32 and float64 division and square root are correctly
// rounded, as Mesa's llvmpipe's are (doc/shading.md, "Normals": the arithmetic, and the bound on
// other GPUs).
//
// Not thread-safe: use it on the thread where its EglContext is current, which must stay alive
// (and current) as long as the producer and any tile it handed out.
#pragma once
#include <memory>

#include "libpyramid/gl/gl_elevation_producer.hpp"
#include "libpyramid/gl/gl_objects.hpp"
#include "libpyramid/runtime/normal_producer.hpp"

namespace pyramid {

struct GlNormalTile {
    int level = 0, tx = 0, ty = 0;
    int size = 0;      // n + 1 texels per side
    GlTexture texture; // RGBA32F (nx, ny, ncx, ncy), row 0 = south
};

class GlNormalProducer {
public:
    // Same contract and options as NormalProducer; the cache holds GPU textures.
    GlNormalProducer(std::shared_ptr<GlElevationProducer> elevations, const NormalProducerOptions& options);
    ~GlNormalProducer();

    int tileSize() const; // n
    std::shared_ptr<const GlNormalTile> tile(int level, int tx, int ty);

    // The tile read back in the CPU producer's form.
    static NormalTile read(const GlNormalTile& tile);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
