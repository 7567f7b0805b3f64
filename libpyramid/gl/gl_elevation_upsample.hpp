// The elevation upsample-and-add of doc/format.md ("Elevation arithmetic") as an OpenGL
// compute shader, bit for bit equal to pyramid::upsampleAndAdd: every value is `precise` (no
// fused multiply-add, no reassociation), the parenthesisation is the CPU code's, samples are
// fetched with texelFetch from R32F textures, and /16 is the exact scaling *0.0625.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/gl/gl_objects.hpp"

namespace pyramid {

// GLSL defining `float predictElevation(ivec2 parentOffset, ivec2 ij)`, the prediction of child
// sample ij. The including shader defines the macro PARENT_Z(x, y) that fetches parent sample
// (x, y) as a float.
const std::string& elevationPredictionGlsl();

class GlElevationUpsampler {
public:
    GlElevationUpsampler(); // compiles the shader: needs a current context
    ~GlElevationUpsampler();

    // out = predictElevation(parent, px, py) + residual over the (n+5)^2 child tile. `parent`
    // and `residual` are R32F textures, `out` an R32F texture of (n+5)^2 texels.
    void run(const GlTexture& parent, int n, int px, int py, const GlTexture& residual, GlTexture& out) const;

    // The same from and to host arrays (row-major, row 0 = bottom): `parent` is parentSide^2
    // floats, `residual` (n+5)^2 floats; returns (n+5)^2 floats.
    std::vector<float> upsampleAndAdd(const std::vector<float>& parent, int parentSide, int n, int px, int py,
                                      const std::vector<float>& residual) const;

private:
    std::unique_ptr<GlProgram> program_;
};

} // namespace pyramid
