#include "libpyramid/gl/gl_colour_upsample.hpp"

#include "formats/error.hpp"

namespace pyramid {

namespace {

constexpr int kLocalSize = 8;

// One invocation per child pixel, all four lanes at once (unused lanes are harmless).
const char* const kOrthoKernel = R"(#version 430 core
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform usampler2D parent;
layout(binding = 1) uniform usampler2D residual;
layout(rgba8ui, binding = 0) writeonly uniform uimage2D result;
uniform ivec2 quadrantOrigin; // (rx, ry) = (tx%2, ty%2) * tileSize/2
uniform int side;             // tileSize + 4
uniform bool hasResidual;

void main() {
    ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= side || xy.y >= side) {
        return;
    }
    ivec2 b = (xy + 1) / 2 + quadrantOrigin;
    // Weight of the b column (b+1 gets 4 minus it): 3 for odd x, 1 for even x; same for rows.
    uint wx0 = (xy.x & 1) != 0 ? 3u : 1u;
    uint wy0 = (xy.y & 1) != 0 ? 3u : 1u;
    uint wx1 = 4u - wx0;
    uint wy1 = 4u - wy0;
    uvec4 sum = wy0 * (wx0 * texelFetch(parent, b, 0) + wx1 * texelFetch(parent, b + ivec2(1, 0), 0)) +
                wy1 * (wx0 * texelFetch(parent, b + ivec2(0, 1), 0) + wx1 * texelFetch(parent, b + ivec2(1, 1), 0));
    ivec4 prediction = ivec4(sum >> 4u);
    ivec4 stored = hasResidual ? ivec4(texelFetch(residual, xy, 0)) : ivec4(128);
    ivec4 value = clamp(prediction + 2 * (stored - 128), 0, 255);
    imageStore(result, xy, uvec4(value));
}
)";

} // namespace

GlColourUpsampler::GlColourUpsampler() : program_(std::make_unique<GlProgram>("ortho upsample", kOrthoKernel)) {}

GlColourUpsampler::~GlColourUpsampler() = default;

void GlColourUpsampler::run(const GlTexture& parent, int tileSize, int tx, int ty, const GlTexture* residual,
                           GlTexture& out) const {
    const int side = tileSize + 4;
    if (parent.width() != side || out.width() != side || (residual != nullptr && residual->width() != side)) {
        fail("GL ortho upsample", "textures do not match the tile size " + std::to_string(tileSize));
    }
    program_->use();
    glUniform2i(program_->uniform("quadrantOrigin"), (tx & 1) * (tileSize / 2), (ty & 1) * (tileSize / 2));
    glUniform1i(program_->uniform("side"), side);
    glUniform1i(program_->uniform("hasResidual"), residual != nullptr ? 1 : 0);
    parent.bind(0);
    // The sampler must see an integer texture even when unused: bind the parent again.
    (residual != nullptr ? *residual : parent).bind(1);
    glBindImageTexture(0, out.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8UI);
    program_->dispatch(side, side, kLocalSize);
}

std::vector<uint8_t> GlColourUpsampler::upsample(const std::vector<uint8_t>& parent, int tileSize, int channels,
                                                int tx, int ty, const std::vector<uint8_t>& residual) const {
    const int side = tileSize + 4;
    const GLenum format = pixelFormat(channels, true);
    GlTexture parentTexture(GL_RGBA8UI, side, side);
    parentTexture.upload(format, GL_UNSIGNED_BYTE, parent.data());
    GlTexture residualTexture(GL_RGBA8UI, side, side);
    if (!residual.empty()) {
        residualTexture.upload(format, GL_UNSIGNED_BYTE, residual.data());
    }
    GlTexture out(GL_RGBA8UI, side, side);
    run(parentTexture, tileSize, tx, ty, residual.empty() ? nullptr : &residualTexture, out);
    std::vector<uint8_t> pixels(static_cast<size_t>(side) * static_cast<size_t>(side) * static_cast<size_t>(channels));
    out.read(format, GL_UNSIGNED_BYTE, pixels.data());
    return pixels;
}

} // namespace pyramid
