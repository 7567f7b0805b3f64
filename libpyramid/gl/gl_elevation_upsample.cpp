#include "libpyramid/gl/gl_elevation_upsample.hpp"

#include "formats/error.hpp"

namespace pyramid {

namespace {

constexpr int kLocalSize = 8;

// The kernel around the prediction: one invocation per child sample.
const char* const kUpsampleKernel = R"(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 1) uniform sampler2D residual;
layout(r32f, binding = 0) writeonly uniform image2D result;
uniform ivec2 parentOffset;
uniform int side;

void main() {
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= side || ij.y >= side) {
        return;
    }
    precise float z = predictElevation(parentOffset, ij) + texelFetch(residual, ij, 0).r;
    imageStore(result, ij, vec4(z, 0.0, 0.0, 0.0));
}
)";

} // namespace

const std::string& elevationPredictionGlsl() {
    static const std::string source = R"(
// doc/format.md, "Elevation arithmetic": ((z1 + z2) * 9 - (z0 + z3)) / 16.
float interpolate4(float z0, float z1, float z2, float z3) {
    precise float s = (z1 + z2) * 9.0 - (z0 + z3);
    precise float r = s * 0.0625;
    return r;
}

// Centre weights (wj * wi), exact multiples of 1/256.
const float kTap[4] = float[4](-0.0625, 0.5625, 0.5625, -0.0625);

float predictElevation(ivec2 parentOffset, ivec2 ij) {
    int x = ij.x / 2 + parentOffset.x;
    int y = ij.y / 2 + parentOffset.y;
    bool oddI = (ij.x & 1) != 0;
    bool oddJ = (ij.y & 1) != 0;
    if (!oddI && !oddJ) {
        return PARENT_Z(x, y);
    }
    if (oddI && !oddJ) {
        return interpolate4(PARENT_Z(x - 1, y), PARENT_Z(x, y), PARENT_Z(x + 1, y), PARENT_Z(x + 2, y));
    }
    if (!oddI && oddJ) {
        return interpolate4(PARENT_Z(x, y - 1), PARENT_Z(x, y), PARENT_Z(x, y + 1), PARENT_Z(x, y + 2));
    }
    // A sum from 0, rows outside, columns inside, each term (wj * wi) * p.
    precise float z = 0.0;
    for (int dj = 0; dj < 4; ++dj) {
        for (int di = 0; di < 4; ++di) {
            precise float w = kTap[dj] * kTap[di];
            z = z + w * PARENT_Z(x + di - 1, y + dj - 1);
        }
    }
    return z;
}
)";
    return source;
}

GlElevationUpsampler::GlElevationUpsampler() {
    const std::string source = "#version 430 core\n#define PARENT_Z(x, y) texelFetch(parentZ, ivec2(x, y), 0).r\n"
                               "layout(binding = 0) uniform sampler2D parentZ;\n" +
                               elevationPredictionGlsl() + kUpsampleKernel;
    program_ = std::make_unique<GlProgram>("elevation upsample", source);
}

GlElevationUpsampler::~GlElevationUpsampler() = default;

void GlElevationUpsampler::run(const GlTexture& parent, int n, int px, int py, const GlTexture& residual,
                               GlTexture& out) const {
    const int side = n + 5;
    if (out.width() != side || out.height() != side || residual.width() != side || residual.height() != side) {
        fail("GL elevation upsample", "textures do not match the tile size " + std::to_string(n));
    }
    program_->use();
    glUniform2i(program_->uniform("parentOffset"), px, py);
    glUniform1i(program_->uniform("side"), side);
    parent.bind(0);
    residual.bind(1);
    glBindImageTexture(0, out.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    program_->dispatch(side, side, kLocalSize);
}

std::vector<float> GlElevationUpsampler::upsampleAndAdd(const std::vector<float>& parent, int parentSide, int n, int px,
                                                        int py, const std::vector<float>& residual) const {
    const int side = n + 5;
    GlTexture parentTexture(GL_R32F, parentSide, parentSide);
    parentTexture.upload(GL_RED, GL_FLOAT, parent.data());
    GlTexture residualTexture(GL_R32F, side, side);
    residualTexture.upload(GL_RED, GL_FLOAT, residual.data());
    GlTexture out(GL_R32F, side, side);
    run(parentTexture, n, px, py, residualTexture, out);
    std::vector<float> z(static_cast<size_t>(side) * static_cast<size_t>(side));
    out.read(GL_RED, GL_FLOAT, z.data());
    return z;
}

} // namespace pyramid
