#include "libpyramid/gl/gl_colour_producer.hpp"

#include <optional>

#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "libpyramid/gl/gl_colour_upsample.hpp"
#include "libpyramid/runtime/tile_cache.hpp"

namespace pyramid {

struct GlColourProducer::Impl {
    std::shared_ptr<const OrthoProducer> residuals;
    TileCache<GlOrthoTile> cache;
    GlColourUpsampler upsampler;

    Impl(std::shared_ptr<const OrthoProducer> producer, size_t capacity)
        : residuals(std::move(producer)), cache(capacity) {}

    // The stored tile (colours at the root, residuals below) in an RGBA8UI texture.
    GlTexture upload(int level, int tx, int ty) const {
        const OrthoHeader& h = residuals->header();
        GlTexture texture(GL_RGBA8UI, h.tilePixels(), h.tilePixels());
        const std::vector<uint8_t> stored = residuals->tile(level, tx, ty);
        texture.upload(pixelFormat(h.channels, true), GL_UNSIGNED_BYTE, stored.data());
        return texture;
    }

    std::shared_ptr<const GlOrthoTile> produce(int level, int tx, int ty) {
        if (auto hit = cache.find({level, tx, ty})) {
            return hit;
        }
        const OrthoHeader& h = residuals->header();
        const int side = h.tilePixels();
        std::shared_ptr<GlOrthoTile> tile;
        if (level == 0) {
            tile = std::make_shared<GlOrthoTile>(GlOrthoTile{0, 0, 0, side, h.channels, false, upload(0, 0, 0)});
        } else {
            const std::shared_ptr<const GlOrthoTile> parent = produce(level - 1, tx / 2, ty / 2);
            std::optional<GlTexture> residual;
            if (residuals->hasTile(level, tx, ty)) {
                residual.emplace(upload(level, tx, ty));
            }
            tile = std::make_shared<GlOrthoTile>(
                GlOrthoTile{level, tx, ty, side, h.channels, false, GlTexture(GL_RGBA8UI, side, side)});
            upsampler.run(parent->texture, h.tileSize, tx, ty, residual ? &*residual : nullptr, tile->texture);
        }
        return cache.insert({level, tx, ty}, std::move(tile));
    }
};

GlColourProducer::GlColourProducer(std::shared_ptr<const OrthoProducer> residuals, size_t cacheCapacity)
    : impl_(std::make_unique<Impl>(std::move(residuals), cacheCapacity)) {
    const OrthoHeader& h = impl_->residuals->header();
    if (h.dxt() || h.border() != 2 || h.tileSize % 2 != 0) {
        fail(impl_->residuals->path(), "colour residual tiles must be TIFF tiles with 2-pixel borders and an even size");
    }
}

GlColourProducer::~GlColourProducer() = default;

const OrthoHeader& GlColourProducer::header() const { return impl_->residuals->header(); }

std::shared_ptr<const GlOrthoTile> GlColourProducer::tile(int level, int tx, int ty) {
    if (!isQuadtreeTile(level, tx, ty)) {
        fail(impl_->residuals->path(),
             "no ortho tile " + tileCoordinates(level, tx, ty));
    }
    return impl_->produce(level, tx, ty);
}

std::vector<uint8_t> GlColourProducer::read(const GlOrthoTile& tile) {
    std::vector<uint8_t> pixels(static_cast<size_t>(tile.size) * static_cast<size_t>(tile.size) *
                                static_cast<size_t>(tile.channels));
    tile.texture.read(pixelFormat(tile.channels, true), GL_UNSIGNED_BYTE, pixels.data());
    return pixels;
}

} // namespace pyramid
