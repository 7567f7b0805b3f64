#include "libpyramid/runtime/elevation_producer.hpp"

#include <algorithm>

#include "formats/error.hpp"
#include "formats/pyramid_file_rules.hpp"
#include "libpyramid/filters/coarse_mesh.hpp"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "libpyramid/runtime/tile_cache.hpp"
#include "libpyramid/runtime/tile_pool.hpp"

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
    const size_t s = static_cast<size_t>(side);
    zc.resize(s * s);
    const auto copyRow = [&](int y, int from, int count) {
        const size_t at = static_cast<size_t>(from) + static_cast<size_t>(y) * s;
        std::copy_n(&zf[at], count, &zc[at]);
    };
    for (int y : {0, 1, n + 3, n + 4}) {
        copyRow(y, 0, side);
    }
    const CoarseMesh mesh(n, gridSize, tx, ty);
    for (int v = 0; v <= n; ++v) {
        copyRow(v + 2, 0, 2);
        copyRow(v + 2, n + 3, 2);
        mesh.mixRow(v, parent.zm().data(), s, &zc[2 + static_cast<size_t>(v + 2) * s]);
    }
}

// The process's elevation tiles that no one holds any more, up to 32 MB (about 70 tiles of 197
// samples): what every producer fills first.
std::shared_ptr<TilePool<ElevationTile>> elevationTilePool() {
    static const std::shared_ptr<TilePool<ElevationTile>> pool =
        TilePool<ElevationTile>::make(size_t{32} << 20, [](const ElevationTile& t) {
            return (t.zf.capacity() + t.zc.capacity()) * sizeof(float);
        });
    return pool;
}

} // namespace

struct ElevationProducer::Impl {
    std::shared_ptr<const ResidualProducer> residuals;
    int n = 0;
    int k = 0; // residual tiles are 2^k elevation tiles wide
    int gridSize = 0;
    TileCache<ElevationTile> cache;
    std::shared_ptr<TilePool<ElevationTile>> pool = elevationTilePool();

    explicit Impl(size_t capacity) : cache(capacity) {}

    std::shared_ptr<const ElevationTile> produce(int level, int tx, int ty) {
        if (auto hit = cache.find({level, tx, ty})) {
            return hit;
        }
        const int side = n + 5;
        std::shared_ptr<ElevationTile> tile = pool->acquire();
        tile->level = level;
        tile->tx = tx;
        tile->ty = ty;
        tile->size = side;
        std::vector<float>& z = tile->zf;
        z.resize(static_cast<size_t>(side) * side);
        // The residual window: tile (level, tx >> k, ty >> k) of the residual producer, from
        // ((tx mod 2^k) * n, (ty mod 2^k) * n). Beyond every file, or left out of the file that
        // holds it (ResidualProducer::hasTile): no residual (R = 0).
        const int rtx = tx >> k, rty = ty >> k;
        const int x0 = (tx & ((1 << k) - 1)) * n, y0 = (ty & ((1 << k) - 1)) * n;
        const bool stored = residuals->hasTile(level, rtx, rty);
        if (level == 0) {
            if (stored) {
                residuals->window(level, rtx, rty, x0, y0, side, z.data(), static_cast<size_t>(side));
            } else {
                std::fill(z.begin(), z.end(), 0.0f);
            }
            tile->zc = z;
        } else {
            // The parent first: its residual tile is decoded before this one's, which the stored
            // window then holds (ResidualProducer::storedWindow).
            const std::shared_ptr<const ElevationTile> parent = produce(level - 1, tx / 2, ty / 2);
            const ResidualWindow r = stored ? residuals->storedWindow(level, rtx, rty, x0, y0, side) : ResidualWindow{};
            upsampleAndAddResiduals(parent->zf.data(), static_cast<size_t>(side), n, quadrantOffset(tx, n),
                                    quadrantOffset(ty, n), r, z.data(), static_cast<size_t>(side));
            coarseElevations(*parent, n, gridSize, tx, ty, z, tile->zc);
        }
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
