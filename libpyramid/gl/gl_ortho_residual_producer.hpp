// Colour tiles rebuilt on the GPU from a colour residual file (doc/format.md, "Colour residual
// files"): the root tile holds plain colours, every other tile is the integer colour upsample
// of its parent plus its stored residual (GlOrthoUpsampler), bit for bit equal to the CPU
// arithmetic of libpyramid/ortho_upsample. Tiles are RGBA8UI textures (texelFetch on a
// usampler2D); the lanes beyond the file's channels are unspecified.
//
// Not thread-safe: use it on the thread where its EglContext is current, which must stay alive
// (and current) as long as the producer and any tile it handed out.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "formats/ortho_file.hpp"
#include "libpyramid/gl/gl_ortho_producer.hpp"

namespace pyramid {

class GlOrthoResidualProducer {
public:
    // Throws Error unless `file` is a TIFF ortho file with 2-pixel borders.
    explicit GlOrthoResidualProducer(const std::string& file, size_t cacheCapacity = 256);
    ~GlOrthoResidualProducer();

    const OrthoHeader& header() const;
    // Throws Error if the file has no tile (level, tx, ty).
    std::shared_ptr<const GlOrthoTile> tile(int level, int tx, int ty);
    // The tile's colours: (tileSize+4)^2 x channels bytes, row 0 = bottom.
    static std::vector<uint8_t> read(const GlOrthoTile& tile);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
