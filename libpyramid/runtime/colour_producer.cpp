#include "libpyramid/runtime/colour_producer.hpp"

#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "libpyramid/filters/colour_upsample.hpp"
#include "libpyramid/runtime/tile_cache.hpp"

namespace pyramid {

struct ColourProducer::Impl {
    std::shared_ptr<const OrthoProducer> residuals;
    TileCache<std::vector<uint8_t>> cache;

    explicit Impl(size_t capacity) : cache(capacity) {}

    std::shared_ptr<const std::vector<uint8_t>> produce(int level, int tx, int ty) {
        if (auto hit = cache.find({level, tx, ty})) {
            return hit;
        }
        std::shared_ptr<std::vector<uint8_t>> out;
        if (level == 0) {
            out = std::make_shared<std::vector<uint8_t>>(residuals->tile(0, 0, 0));
        } else {
            const auto parent = produce(level - 1, tx / 2, ty / 2);
            const OrthoHeader& h = residuals->header();
            out = std::make_shared<std::vector<uint8_t>>(parent->size());
            if (residuals->hasTile(level, tx, ty)) {
                const std::vector<uint8_t> r = residuals->tile(level, tx, ty);
                upsampleColour(parent->data(), h.tileSize, h.channels, tx, ty, r.data(), out->data());
            } else {
                upsampleColour(parent->data(), h.tileSize, h.channels, tx, ty, nullptr, out->data());
            }
        }
        return cache.insert({level, tx, ty}, std::move(out));
    }
};

ColourProducer::ColourProducer(std::shared_ptr<const OrthoProducer> residuals, size_t cacheCapacity)
    : impl_(std::make_unique<Impl>(cacheCapacity)) {
    const OrthoHeader& h = residuals->header();
    if (h.border() != 2 || h.dxt()) {
        fail(residuals->path(), "colour residual tiles must be TIFF tiles with 2-pixel borders");
    }
    if (h.tileSize % 2 != 0) {
        fail(residuals->path(), "colour residual tiles need an even tile size, not " + std::to_string(h.tileSize));
    }
    impl_->residuals = std::move(residuals);
}

ColourProducer::~ColourProducer() = default;

int ColourProducer::tilePixels() const { return impl_->residuals->header().tilePixels(); }
int ColourProducer::channels() const { return impl_->residuals->header().channels; }

std::shared_ptr<const std::vector<uint8_t>> ColourProducer::tile(int level, int tx, int ty) {
    if (!isQuadtreeTile(level, tx, ty)) {
        fail(impl_->residuals->path(),
             "no ortho tile " + tileCoordinates(level, tx, ty));
    }
    return impl_->produce(level, tx, ty);
}

} // namespace pyramid
