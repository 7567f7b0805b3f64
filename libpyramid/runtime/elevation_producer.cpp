#include "libpyramid/runtime/elevation_producer.hpp"

#include <algorithm>

#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "libpyramid/filters/coarse_mesh.hpp"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "libpyramid/runtime/tile_cache.hpp"

namespace pyramid {

int elevationDelta(const ResidualHeader& header, int n, const std::string& where) {
    int k = 0;
    while (k <= header.minLevel && (header.tileSize >> k) > n) {
        ++k;
    }
    if (n < 2 || n % 2 != 0 || k > header.minLevel || (header.tileSize >> k) != n || (n << k) != header.tileSize) {
        fail(where, "elevation tiles of " + std::to_string(n) + " need tileSize / 2^k for k in 0.." +
                     std::to_string(header.minLevel) + " (tileSize " + std::to_string(header.tileSize) + ")");
    }
    return header.minLevel - k;
}

ElevationTiling elevationTiling(const ResidualProducer& residuals, const ElevationProducerOptions& options) {
    const ResidualHeader& h = residuals.header();
    ElevationTiling t;
    t.n = options.tileSize == 0 ? h.tileSize : options.tileSize;
    const int delta = elevationDelta(h, t.n, residuals.path());
    if (delta != residuals.delta()) {
        fail(residuals.path(), "elevation tiles of " + std::to_string(t.n) + " need a residual producer with delta " +
                                   std::to_string(delta) + ", not " + std::to_string(residuals.delta()));
    }
    t.k = h.minLevel - delta;
    t.gridSize = options.gridSize == 0 ? t.n : options.gridSize;
    if (t.gridSize < 2 || t.gridSize % 2 != 0 || t.n % t.gridSize != 0) {
        fail(residuals.path(), "gridSize " + std::to_string(t.gridSize) +
                                   " must be even and divide the elevation tile size " + std::to_string(t.n));
    }
    return t;
}

namespace {

// zc, the coarse elevation: the parent's zm on its render mesh at every interior sample
// (filters/coarse_mesh.hpp). Border samples (outside 0..n) are not rendered: their zc is their zf.
void coarseElevations(const ElevationTile& parent, int n, int gridSize, int tx, int ty, const std::vector<float>& zf,
                      std::vector<float>& zc) {
    const int side = n + 5;
    zc = zf;
    const CoarseMesh mesh(n, gridSize, tx, ty);
    const auto zm = [&](int x, int y) { return parent.zm[static_cast<size_t>(x + y * side)]; };
    for (int v = 0; v <= n; ++v) {
        for (int u = 0; u <= n; ++u) {
            const CoarseMesh::At a = mesh.at(u, v);
            zc[static_cast<size_t>((u + 2) + (v + 2) * side)] =
                coarseMix(a, zm(a.x0, a.y0), zm(a.x1, a.y0), zm(a.x0, a.y1), a.lower ? 0.0f : zm(a.x1, a.y1));
        }
    }
}

} // namespace

struct ElevationProducer::Impl {
    std::shared_ptr<const ResidualProducer> residuals;
    int n = 0;
    int k = 0; // residual tiles are 2^k elevation tiles wide
    int gridSize = 0;
    TileCache<ElevationTile> cache;

    explicit Impl(size_t capacity) : cache(capacity) {}

    std::shared_ptr<const ElevationTile> produce(int level, int tx, int ty) {
        if (auto hit = cache.find({level, tx, ty})) {
            return hit;
        }
        const int side = n + 5;
        auto tile = std::make_shared<ElevationTile>();
        tile->level = level;
        tile->tx = tx;
        tile->ty = ty;
        tile->size = side;
        std::vector<float>& z = tile->zf;
        z.assign(static_cast<size_t>(side) * side, 0.0f);
        // The residual window: tile (level, tx >> k, ty >> k) of the residual producer, from
        // ((tx mod 2^k) * n, (ty mod 2^k) * n). Beyond every file, or left out of the file that
        // holds it (ResidualProducer::hasTile): no residual (R = 0).
        const int rtx = tx >> k, rty = ty >> k;
        if (residuals->hasTile(level, rtx, rty)) {
            const std::vector<float> r = residuals->tile(level, rtx, rty);
            const size_t stride = static_cast<size_t>(residuals->tileSize()) + 5;
            const size_t x0 = static_cast<size_t>(tx & ((1 << k) - 1)) * static_cast<size_t>(n);
            const size_t y0 = static_cast<size_t>(ty & ((1 << k) - 1)) * static_cast<size_t>(n);
            for (int j = 0; j < side; ++j) {
                std::copy_n(&r[x0 + (y0 + static_cast<size_t>(j)) * stride], side, &z[static_cast<size_t>(j) * side]);
            }
        }
        if (level == 0) {
            tile->zc = z;
        } else {
            const std::shared_ptr<const ElevationTile> parent = produce(level - 1, tx / 2, ty / 2);
            upsampleAndAdd(parent->zf.data(), static_cast<size_t>(side), n, quadrantOffset(tx, n),
                           quadrantOffset(ty, n), z.data(), static_cast<size_t>(side));
            coarseElevations(*parent, n, gridSize, tx, ty, z, tile->zc);
        }
        tile->zm = z;
        return cache.insert({level, tx, ty}, std::move(tile));
    }
};

ElevationProducer::ElevationProducer(std::shared_ptr<const ResidualProducer> residuals,
                                     const ElevationProducerOptions& options)
    : impl_(std::make_unique<Impl>(options.cacheCapacity)) {
    const ElevationTiling t = elevationTiling(*residuals, options);
    impl_->residuals = std::move(residuals);
    impl_->n = t.n;
    impl_->k = t.k;
    impl_->gridSize = t.gridSize;
}

ElevationProducer::~ElevationProducer() = default;

FileLevelProducer makeFileLevelProducer(const std::string& file, int fileLevel, size_t cacheCapacity) {
    auto header = ResidualFileReader::readHeader(file);
    if (fileLevel < 0 || fileLevel > header.maxLevel) {
        fail(file, "no level " + std::to_string(fileLevel) + " (levels 0.." + std::to_string(header.maxLevel) + ")");
    }
    FileLevelProducer p;
    p.delta = std::min(fileLevel, header.minLevel);
    p.n = header.tileSize >> (header.minLevel - p.delta);
    ResidualProducerOptions ro;
    ro.delta = p.delta;
    auto residuals = std::make_shared<ResidualProducer>(file, std::vector<std::string>{}, ro);
    ElevationProducerOptions eo;
    eo.tileSize = p.n;
    eo.cacheCapacity = cacheCapacity;
    p.producer = std::make_shared<ElevationProducer>(residuals, eo);
    return p;
}

int ElevationProducer::tileSize() const { return impl_->n; }
int ElevationProducer::gridSize() const { return impl_->gridSize; }
int ElevationProducer::maxLevel() const { return impl_->residuals->maxLevel(); }
bool ElevationProducer::hasResiduals(int level, int tx, int ty) const {
    return impl_->residuals->hasTile(level, tx >> impl_->k, ty >> impl_->k);
}
const std::string& ElevationProducer::path() const { return impl_->residuals->path(); }

std::shared_ptr<const ElevationTile> ElevationProducer::tile(int level, int tx, int ty) {
    if (!isQuadtreeTile(level, tx, ty)) {
        fail(impl_->residuals->path(), "no elevation tile " + tileCoordinates(level, tx, ty));
    }
    return impl_->produce(level, tx, ty);
}

} // namespace pyramid
