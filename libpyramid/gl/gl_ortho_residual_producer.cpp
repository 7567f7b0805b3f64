#include "libpyramid/gl/gl_ortho_residual_producer.hpp"

#include "formats/error.hpp"
#include "libpyramid/gl/gl_ortho_upsample.hpp"
#include "libpyramid/tile_cache.hpp"

namespace pyramid {

struct GlOrthoResidualProducer::Impl {
    std::unique_ptr<OrthoFileReader> reader;
    TileCache<GlOrthoTile> cache;
    GlOrthoUpsampler upsampler;

    Impl(const std::string& file, size_t capacity) : reader(OrthoFileReader::open(file)), cache(capacity) {}

    // The stored tile (colours at the root, residuals below) in an RGBA8UI texture.
    GlTexture upload(int level, int tx, int ty) const {
        const OrthoHeader& h = reader->header();
        GlTexture texture(GL_RGBA8UI, h.tilePixels(), h.tilePixels());
        const std::vector<uint8_t> stored = reader->readTile(level, tx, ty);
        texture.upload(pixelFormat(h.channels, true), GL_UNSIGNED_BYTE, stored.data());
        return texture;
    }

    std::shared_ptr<const GlOrthoTile> produce(int level, int tx, int ty) {
        if (auto hit = cache.find({level, tx, ty})) {
            return hit;
        }
        const OrthoHeader& h = reader->header();
        if (!h.contains(level, tx, ty)) {
            fail(reader->path(), "no tile (" + std::to_string(level) + "," + std::to_string(tx) + "," +
                                     std::to_string(ty) + ") in this file");
        }
        const int side = h.tilePixels();
        std::shared_ptr<GlOrthoTile> tile;
        if (level == 0) {
            tile = std::make_shared<GlOrthoTile>(GlOrthoTile{0, tx, ty, side, h.channels, false, upload(0, tx, ty)});
        } else {
            const std::shared_ptr<const GlOrthoTile> parent = produce(level - 1, tx / 2, ty / 2);
            const GlTexture residual = upload(level, tx, ty);
            tile = std::make_shared<GlOrthoTile>(
                GlOrthoTile{level, tx, ty, side, h.channels, false, GlTexture(GL_RGBA8UI, side, side)});
            upsampler.run(parent->texture, h.tileSize, tx, ty, &residual, tile->texture);
        }
        return cache.insert({level, tx, ty}, std::move(tile));
    }
};

GlOrthoResidualProducer::GlOrthoResidualProducer(const std::string& file, size_t cacheCapacity)
    : impl_(std::make_unique<Impl>(file, cacheCapacity)) {
    const OrthoHeader& h = impl_->reader->header();
    if (h.dxt() || h.border() != 2) {
        fail(file, "colour residuals need TIFF tiles with 2-pixel borders");
    }
}

GlOrthoResidualProducer::~GlOrthoResidualProducer() = default;

const OrthoHeader& GlOrthoResidualProducer::header() const { return impl_->reader->header(); }

std::shared_ptr<const GlOrthoTile> GlOrthoResidualProducer::tile(int level, int tx, int ty) {
    return impl_->produce(level, tx, ty);
}

std::vector<uint8_t> GlOrthoResidualProducer::read(const GlOrthoTile& tile) {
    std::vector<uint8_t> pixels(static_cast<size_t>(tile.size) * static_cast<size_t>(tile.size) *
                                static_cast<size_t>(tile.channels));
    tile.texture.read(pixelFormat(tile.channels, true), GL_UNSIGNED_BYTE, pixels.data());
    return pixels;
}

} // namespace pyramid
