#include "libpyramid/gl/gl_ortho_producer.hpp"

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"
#include "libpyramid/runtime/tile_cache.hpp"

namespace pyramid {

namespace {

constexpr int kLocalSize = 8;

// Samples every texel as the GPU decodes it and stores it as unsigned normalised bytes.
const char* const kSampleKernel = R"(#version 430 core
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D tile;
layout(rgba8, binding = 0) writeonly uniform image2D result;
uniform int side;

void main() {
    ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x < side && xy.y < side) {
        imageStore(result, xy, texelFetch(tile, xy, 0));
    }
}
)";

GLenum normalizedInternalFormat(int channels) {
    static constexpr GLenum kFormats[4] = {GL_R8, GL_RG8, GL_RGB8, GL_RGBA8};
    return kFormats[channels - 1];
}

} // namespace

struct GlOrthoProducer::Impl {
    std::shared_ptr<const OrthoProducer> tiles;
    TileCache<GlOrthoTile> cache;
    GlProgram sampler{"ortho sampling", kSampleKernel};

    Impl(std::shared_ptr<const OrthoProducer> producer, size_t capacity) : tiles(std::move(producer)), cache(capacity) {}
};

GlOrthoProducer::GlOrthoProducer(std::shared_ptr<const OrthoProducer> tiles, size_t cacheCapacity)
    : impl_(std::make_unique<Impl>(std::move(tiles), cacheCapacity)) {}

GlOrthoProducer::~GlOrthoProducer() = default;

const OrthoHeader& GlOrthoProducer::header() const { return impl_->tiles->header(); }

std::shared_ptr<const GlOrthoTile> GlOrthoProducer::tile(int level, int tx, int ty) {
    if (auto hit = impl_->cache.find({level, tx, ty})) {
        return hit;
    }
    const OrthoHeader& h = header();
    const int side = h.tilePixels();
    std::shared_ptr<GlOrthoTile> tile;
    if (h.dxt()) {
        const bool dxt5 = h.channels == 4;
        tile = std::make_shared<GlOrthoTile>(GlOrthoTile{
            level, tx, ty, side, dxt5 ? 4 : 3, true,
            GlTexture(dxt5 ? GL_COMPRESSED_RGBA_S3TC_DXT5_EXT : GL_COMPRESSED_RGB_S3TC_DXT1_EXT, side, side)});
        const std::vector<uint8_t> blocks = impl_->tiles->rawTile(level, tx, ty);
        if (blocks.size() != dxtBytes(side, side, dxt5 ? DxtFormat::Dxt5 : DxtFormat::Dxt1)) {
            fail("GL ortho",
                 "DXT tile " + tileCoordinates(level, tx, ty) + " has " + std::to_string(blocks.size()) + " bytes");
        }
        tile->texture.uploadCompressed(blocks.data(), blocks.size());
    } else {
        tile = std::make_shared<GlOrthoTile>(
            GlOrthoTile{level, tx, ty, side, h.channels, false, GlTexture(normalizedInternalFormat(h.channels), side, side)});
        const std::vector<uint8_t> pixels = impl_->tiles->tile(level, tx, ty);
        tile->texture.upload(pixelFormat(h.channels, false), GL_UNSIGNED_BYTE, pixels.data());
    }
    return impl_->cache.insert({level, tx, ty}, std::move(tile));
}

std::vector<uint8_t> GlOrthoProducer::readCompressed(const GlOrthoTile& tile) {
    if (!tile.compressed) {
        fail("GL ortho", "tile (" + std::to_string(tile.level) + "," + std::to_string(tile.tx) + "," +
                             std::to_string(tile.ty) + ") is not compressed");
    }
    return tile.texture.readCompressed();
}

std::vector<uint8_t> GlOrthoProducer::readPixels(const GlOrthoTile& tile) const {
    GlTexture out(GL_RGBA8, tile.size, tile.size);
    impl_->sampler.use();
    glUniform1i(impl_->sampler.uniform("side"), tile.size);
    tile.texture.bind(0);
    glBindImageTexture(0, out.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    impl_->sampler.dispatch(tile.size, tile.size, kLocalSize);
    std::vector<uint8_t> pixels(static_cast<size_t>(tile.size) * static_cast<size_t>(tile.size) *
                                static_cast<size_t>(tile.channels));
    out.read(pixelFormat(tile.channels, false), GL_UNSIGNED_BYTE, pixels.data());
    return pixels;
}

} // namespace pyramid
