#include "libpyramid/runtime/normal_producer.hpp"

#include <cmath>

#include "formats/error.hpp"
#include "libpyramid/runtime/tile_cache.hpp"

namespace pyramid {

struct NormalProducer::Impl {
    std::shared_ptr<ElevationProducer> elevations;
    NormalProducerOptions options;
    TileCache<NormalTile> cache;

    Impl(std::shared_ptr<ElevationProducer> e, const NormalProducerOptions& o)
        : elevations(std::move(e)), options(o), cache(o.cacheCapacity) {}
};

void checkNormalOptions(const NormalProducerOptions& options, const std::string& where) {
    if (!(options.size > 0.0) || !std::isfinite(options.size)) {
        fail(where, std::string("normals need the ") +
                        (options.deformation == Deformation::Sphere ? "sphere's radius" : "root quad's size") +
                        " in height units, a positive number");
    }
}

NormalProducer::NormalProducer(std::shared_ptr<ElevationProducer> elevations, const NormalProducerOptions& options)
    : impl_(std::make_unique<Impl>(std::move(elevations), options)) {
    checkNormalOptions(options, impl_->elevations->path());
}

NormalProducer::~NormalProducer() = default;

int NormalProducer::tileSize() const { return impl_->elevations->tileSize(); }
const NormalProducerOptions& NormalProducer::options() const { return impl_->options; }

std::shared_ptr<const NormalTile> NormalProducer::tile(int level, int tx, int ty) {
    if (auto hit = impl_->cache.find({level, tx, ty})) {
        return hit;
    }
    const int n = impl_->elevations->tileSize();
    const NormalProducerOptions& o = impl_->options;
    const auto heights = impl_->elevations->tile(level, tx, ty); // checks the coordinates
    std::shared_ptr<const ElevationTile> parent;
    NormalGeometry parentGeometry;
    if (level > 0) {
        parent = impl_->elevations->tile(level - 1, tx / 2, ty / 2);
        parentGeometry = normalGeometry(o.deformation, o.size, n, level - 1, tx / 2, ty / 2);
    }
    auto tile = std::make_shared<NormalTile>();
    tile->level = level;
    tile->tx = tx;
    tile->ty = ty;
    tile->size = n + 1;
    tile->normals.resize(static_cast<size_t>(n + 1) * static_cast<size_t>(n + 1) * 4);
    normalTile(heights->zm().data(), normalGeometry(o.deformation, o.size, n, level, tx, ty),
               parent ? parent->zm().data() : nullptr, parentGeometry, n, impl_->elevations->gridSize(), tx, ty,
               tile->normals.data());
    return impl_->cache.insert({level, tx, ty}, std::move(tile));
}

} // namespace pyramid
