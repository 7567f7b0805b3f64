// The colour-residual upsample of doc/format.md ("Colour residual arithmetic") as an OpenGL
// compute shader, bit for bit equal to pyramid::upsampleColour: integer arithmetic only
// (uint sums, >> 4, clamp), pixels fetched with texelFetch from RGBA8UI textures. Tiles of 1 to
// 4 channels all live in RGBA8UI textures; the unused channels are ignored.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "libpyramid/gl/gl_objects.hpp"

namespace pyramid {

class GlColourUpsampler {
public:
    GlColourUpsampler(); // compiles the shader: needs a current context
    ~GlColourUpsampler();

    // out = applyColourResidual(predictColour(parent, quadrant of (tx, ty)), residual) over the
    // (tileSize+4)^2 child tile. All three are RGBA8UI textures of (tileSize+4)^2 texels;
    // residual = nullptr means "no residual" (every stored value 128).
    void run(const GlTexture& parent, int tileSize, int tx, int ty, const GlTexture* residual, GlTexture& out) const;

    // The same from and to host arrays of (tileSize+4)^2 x channels bytes, row 0 = bottom;
    // an empty `residual` means none.
    std::vector<uint8_t> upsample(const std::vector<uint8_t>& parent, int tileSize, int channels, int tx, int ty,
                                  const std::vector<uint8_t>& residual) const;

private:
    std::unique_ptr<GlProgram> program_;
};

} // namespace pyramid
