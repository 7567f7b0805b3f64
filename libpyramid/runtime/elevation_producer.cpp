#include "libpyramid/runtime/elevation_producer.hpp"

#include <algorithm>

#include "formats/error.hpp"
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

// zc, the coarse elevation (doc/format.md, 3.1 "Coarse elevations"): the parent tile's render mesh,
// a grid of gridSize quads over the parent quad with north-west to south-east diagonals,
// evaluated at the child sample. Over the child quad that mesh has cells of c = 2n / gridSize
// child samples. For interior sample u = i - 2, v = j - 2 (0..n):
//   cx = min(u / c, gridSize/2 - 1), fx = (u - cx*c) / c   (likewise cy, fy; exact fractions)
//   corners zAB = parent zm at child position ((cx+A)*c, (cy+B)*c), i.e. parent sample
//   ((cx+A)*c/2 + (tx%2)*n/2 + 2, (cy+B)*c/2 + (ty%2)*n/2 + 2)
//   lower-left triangle (fx + fy <= 1): zc = ((1-fx-fy) * z00 + fx * z10) + fy * z01
//   upper-right triangle (fx + fy > 1): zc = ((fx+fy-1) * z11 + (1-fy) * z10) + (1-fx) * z01
// float32, this order; the weights are exact, so a sample on a parent mesh vertex copies it.
// Border samples (outside 0..n) are not rendered: their zc is their zf.
void coarseElevations(const ElevationTile& parent, int n, int gridSize, int tx, int ty, const std::vector<float>& zf,
                      std::vector<float>& zc) {
    const int side = n + 5;
    zc = zf;
    const int c = 2 * n / gridSize;
    const int cells = gridSize / 2;
    const int ox = (tx & 1) * (n / 2) + 2;
    const int oy = (ty & 1) * (n / 2) + 2;
    const float invC = 1.0f / static_cast<float>(c);
    auto zm = [&](int cellX, int cellY) {
        const int px = cellX * c / 2 + ox;
        const int py = cellY * c / 2 + oy;
        return parent.zm[static_cast<size_t>(px + py * side)];
    };
    for (int v = 0; v <= n; ++v) {
        const int cy = std::min(v / c, cells - 1);
        const float fy = static_cast<float>(v - cy * c) * invC;
        for (int u = 0; u <= n; ++u) {
            const int cx = std::min(u / c, cells - 1);
            const float fx = static_cast<float>(u - cx * c) * invC;
            const float z00 = zm(cx, cy), z10 = zm(cx + 1, cy), z01 = zm(cx, cy + 1);
            float z;
            if (fx + fy <= 1.0f) {
                z = ((1.0f - fx - fy) * z00 + fx * z10) + fy * z01;
            } else {
                const float z11 = zm(cx + 1, cy + 1);
                z = ((fx + fy - 1.0f) * z11 + (1.0f - fy) * z10) + (1.0f - fx) * z01;
            }
            zc[static_cast<size_t>((u + 2) + (v + 2) * side)] = z;
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
        // ((tx mod 2^k) * n, (ty mod 2^k) * n). Beyond every file: no residual (R = 0).
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
int ElevationProducer::maxLevel() const { return impl_->residuals->maxLevel(); }

std::shared_ptr<const ElevationTile> ElevationProducer::tile(int level, int tx, int ty) {
    if (level < 0 || level > 30 || tx < 0 || ty < 0 || tx >= (1 << level) || ty >= (1 << level)) {
        fail(impl_->residuals->path(), "no elevation tile (" + std::to_string(level) + "," + std::to_string(tx) + "," +
                                           std::to_string(ty) + ")");
    }
    return impl_->produce(level, tx, ty);
}

} // namespace pyramid
