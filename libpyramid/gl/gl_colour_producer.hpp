// ColourProducer on the GPU: colour tiles rebuilt from colour residual files (doc/format.md,
// "Colour residual files"). The root tile holds plain colours, every other tile is the integer
// colour upsample of its parent plus its stored residual (GlColourUpsampler), or plus no residual
// (128) beyond the files' deepest level, bit for bit equal to the CPU producer. Tiles are RGBA8UI
// textures (texelFetch on a usampler2D); the lanes beyond the files' channels are unspecified.
//
// Not thread-safe: use it on the thread where its EglContext is current, which must stay alive
// (and current) as long as the producer and any tile it handed out.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "libpyramid/gl/gl_ortho_producer.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"

namespace pyramid {

class GlColourProducer {
public:
    // Throws Error unless the residual tiles are TIFF tiles with 2-pixel borders and an even size.
    explicit GlColourProducer(std::shared_ptr<const OrthoProducer> residuals, size_t cacheCapacity = 256);
    ~GlColourProducer();

    const OrthoHeader& header() const;
    // Any tile of levels 0..30; throws Error for coordinates outside the quadtree.
    std::shared_ptr<const GlOrthoTile> tile(int level, int tx, int ty);
    // The tile's colours: (tileSize+4)^2 x channels bytes, row 0 = bottom.
    static std::vector<uint8_t> read(const GlOrthoTile& tile);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
