// Ortho tiles on the GPU, as the original OrthoGPUProducer holds them: the tiles of a CPU
// OrthoProducer (a main file and its regions) uploaded as textures, TIFF tiles decoded on the
// CPU into GL_R8 .. GL_RGBA8 textures, DXT
// tiles uploaded unchanged as GL_COMPRESSED_RGB_S3TC_DXT1_EXT / GL_COMPRESSED_RGBA_S3TC_DXT5_EXT
// textures (the GPU decodes them when sampling).
//
// Not thread-safe: use it on the thread where its EglContext is current, which must stay alive
// (and current) as long as the producer and any tile it handed out.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "libpyramid/gl/gl_objects.hpp"
#include "libpyramid/runtime/ortho_producer.hpp"

namespace pyramid {

struct GlOrthoTile {
    int level = 0, tx = 0, ty = 0;
    int size = 0;      // pixels per side as stored (tileSize, + 4 with borders)
    int channels = 0;  // the channels the texture holds (3 for DXT1, 4 for DXT5)
    bool compressed = false;
    GlTexture texture; // row 0 = bottom
};

class GlOrthoProducer {
public:
    explicit GlOrthoProducer(std::shared_ptr<const OrthoProducer> tiles, size_t cacheCapacity = 256);
    ~GlOrthoProducer();

    const OrthoHeader& header() const;
    // Throws Error if no file has the tile (level, tx, ty).
    std::shared_ptr<const GlOrthoTile> tile(int level, int tx, int ty);

    // A DXT tile's blocks as the driver holds them (glGetCompressedTexImage): the file's
    // bytes, unchanged.
    static std::vector<uint8_t> readCompressed(const GlOrthoTile& tile);
    // The pixels as a shader samples them (texelFetch, stored into an RGBA8 image):
    // size^2 x channels bytes, row 0 = bottom. For DXT tiles this is the GPU's decoder.
    std::vector<uint8_t> readPixels(const GlOrthoTile& tile) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
