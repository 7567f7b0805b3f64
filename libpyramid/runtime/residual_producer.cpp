#include "libpyramid/runtime/residual_producer.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <utility>

#include "formats/error.hpp"
#include "formats/vector_clones.hpp"
#include "libpyramid/filters/elevation_upsample.hpp"
#include "libpyramid/runtime/region_lookup.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

void ResidualProducerOptions::validate() const {
    if (!std::isfinite(scale) || scale == 0.0f) {
        failOption("scale", numberText(scale) + " is not a finite non-zero number");
    }
}

namespace {

// out[i] = r[i] * scale for i < n, then zeros up to `side`: one row of a residual window.
PYRAMID_VECTOR_CLONES
void scaleRow(const int16_t* r, int n, float scale, int side, float* out) {
    for (int i = 0; i < n; ++i) {
        out[i] = static_cast<float>(r[i]) * scale;
    }
    for (int i = n; i < side; ++i) {
        out[i] = 0.0f;
    }
}

// The residual tile a thread decoded last, and whose it is: elevation tiles smaller than the
// residual tiles (n = tileSize / 2^k, k > 0) are 4^k windows of one residual tile, produced one
// after the other as a renderer descends, and each would decode the whole tile again.
struct LastTile {
    uint64_t producer = 0; // Impl::id; 0 while nothing is held
    size_t file = 0;
    int level = 0, tx = 0, ty = 0;
    std::vector<int16_t> residuals;
};

// Every producer's own number, never reused: a producer made where another one was destroyed
// does not take that one's tile.
uint64_t nextProducerId() {
    static std::atomic<uint64_t> next{1};
    return next.fetch_add(1, std::memory_order_relaxed);
}

} // namespace

struct ResidualProducer::Impl {
    const uint64_t id = nextProducerId();
    std::vector<std::unique_ptr<ResidualFileReader>> files; // main file first
    std::vector<float> scales;                               // file scale x producer scale
    int delta = 0;
    int tileSize = 0;
    int maxLevel = 0;

    // Whether absolute file tile (level, tx, ty) has residuals (ResidualProducer::hasTile).
    bool stored(int level, int tx, int ty) const {
        RelativeTile rel;
        return deepestStorer(files, level, tx, ty, rel) >= 0;
    }

    // The residuals of absolute file tile (level, tx, ty), its samples [x0, x0 + side) x
    // [y0, y0 + side), as stored (ResidualWindow: none past the tile's own samples, nor where the
    // tile is left out, an empty byte range), held in this thread's last tile. `samples` is set
    // to the tile's samples per side.
    ResidualWindow stored(int level, int tx, int ty, int x0, int y0, int side, int& samples) const {
        RelativeTile rel;
        const int k = deepestHolder(files, level, tx, ty, rel);
        if (k < 0) {
            throw MissingTileError(files.front()->path() + ": no residual tile " + tileCoordinates(level, tx, ty) +
                                   " in any file");
        }
        const ResidualFileReader& f = *files[static_cast<size_t>(k)];
        const int s = f.header().tileSamples(rel.level);
        samples = s;
        ResidualWindow w;
        w.scale = scales[static_cast<size_t>(k)];
        if (!storesTile(f, rel)) {
            return w;
        }
        thread_local LastTile last;
        const bool held = last.producer == id && last.file == static_cast<size_t>(k) && last.level == rel.level &&
                          last.tx == rel.tx && last.ty == rel.ty;
        if (!held) {
            last.producer = 0; // nothing held until the tile is decoded (a failed read leaves none)
            last.residuals.resize(static_cast<size_t>(s) * static_cast<size_t>(s));
            f.readTileInto(rel.level, rel.tx, rel.ty, last.residuals);
            last.producer = id;
            last.file = static_cast<size_t>(k);
            last.level = rel.level;
            last.tx = rel.tx;
            last.ty = rel.ty;
        }
        // Columns x0 .. x0 + columns - 1 and rows below s hold samples of the tile.
        w.columns = std::clamp(s - x0, 0, side);
        w.rows = std::clamp(s - y0, 0, side);
        w.stride = static_cast<size_t>(s);
        if (w.columns > 0 && w.rows > 0) {
            w.first = &last.residuals[static_cast<size_t>(x0) + static_cast<size_t>(y0) * w.stride];
        } else {
            w.columns = w.rows = 0;
        }
        return w;
    }

    // The scaled residuals of stored(): float(r) * scale, zeros elsewhere, into `out` (rows
    // `stride` apart). Returns the tile's samples per side.
    int load(int level, int tx, int ty, int x0, int y0, int side, float* out, size_t stride) const {
        int s = 0;
        const ResidualWindow w = stored(level, tx, ty, x0, y0, side, s);
        for (int j = 0; j < side; ++j) {
            const int n = j < w.rows ? w.columns : 0;
            scaleRow(n > 0 ? w.first + static_cast<size_t>(j) * w.stride : nullptr, n, w.scale, side,
                     out + static_cast<size_t>(j) * stride);
        }
        return s;
    }

    // The root with delta > 0: the upsample-and-add of file levels 0..delta, each a whole-tile 2x
    // upsample (all these levels are at or below minLevel, one tile each). `a` and `b` are
    // resized to whole tiles (every sample written before it is read); returns the one holding
    // the root.
    std::vector<float>& root(std::vector<float>& a, std::vector<float>& b) const {
        const size_t stride = static_cast<size_t>(tileSize) + 5;
        const int whole = static_cast<int>(stride);
        a.resize(stride * stride);
        b.resize(stride * stride);
        std::vector<float>* parent = &a;
        std::vector<float>* out = &b;
        load(0, 0, 0, 0, 0, whole, parent->data(), stride);
        for (int l = 1; l <= delta; ++l) {
            const int s = load(l, 0, 0, 0, 0, whole, out->data(), stride);
            upsampleAndAdd(parent->data(), stride, s - 5, 1, 1, out->data(), stride);
            std::swap(parent, out);
        }
        return *parent;
    }
};

ResidualProducer::ResidualProducer(const std::string& mainFile, const std::vector<std::string>& regions,
                                   const ResidualProducerOptions& options)
    : ResidualProducer(openFileSource(mainFile), openFileSources(regions), options) {}

ResidualProducer::ResidualProducer(std::shared_ptr<const ByteSource> mainFile,
                                   const std::vector<std::shared_ptr<const ByteSource>>& regions,
                                   const ResidualProducerOptions& options)
    : impl_(std::make_unique<Impl>()) {
    options.validate();
    auto addFile = [&](std::shared_ptr<const ByteSource> source) {
        impl_->files.push_back(ResidualFileReader::open(std::move(source)));
        const float fileScale = impl_->files.back()->header().scale;
        const float product = fileScale * options.scale;
        // The option must keep every residual a finite non-zero float where the file's own scale
        // does: the product overflowing (or the largest residual, -32768, times it) or
        // underflowing to 0 would serve infinities, NaNs or flat zeros for the file's heights. (A
        // file whose own scale overflows is served as it is: verification reports its heights.)
        const bool fileFinite = std::isfinite(fileScale * -32768.0f);
        if ((fileFinite && !std::isfinite(product * -32768.0f)) || product == 0.0f) {
            failOption("scale", numberText(options.scale) + " times the scale of " +
                                    impl_->files.back()->path() + " (" + numberText(fileScale) + ") " +
                                    (product == 0.0f ? "underflows to 0" : "puts its residuals beyond float's range"));
        }
        impl_->scales.push_back(product);
    };
    addFile(std::move(mainFile));
    const ResidualHeader& main = impl_->files.front()->header();
    const std::string& mainName = impl_->files.front()->path();
    if (main.rootLevel != 0) {
        fail(mainName, "the main file of a residual producer must be rooted at tile (0,0,0)");
    }
    for (const auto& region : regions) {
        addFile(region);
        const ResidualHeader& h = impl_->files.back()->header();
        const std::string& name = impl_->files.back()->path();
        if (h.tileSize != main.tileSize) {
            fail(name, "region tileSize " + std::to_string(h.tileSize) + " differs from the main file's " +
                           std::to_string(main.tileSize));
        }
        if (h.rootLevel < std::max(1, main.minLevel)) {
            fail(name, "a region file must be rooted at level 1 or deeper, and not above the main file's "
                       "minLevel (" + std::to_string(main.minLevel) + ")");
        }
    }
    if (options.delta < 0 || options.delta > main.minLevel) {
        fail(mainName, "delta " + std::to_string(options.delta) + " is outside 0.." + std::to_string(main.minLevel));
    }
    impl_->delta = options.delta;
    impl_->tileSize = main.tileSize;
    for (const auto& f : impl_->files) {
        impl_->maxLevel = std::max(impl_->maxLevel, f->header().rootLevel + f->header().maxLevel);
    }
    impl_->maxLevel -= impl_->delta;
}

ResidualProducer::~ResidualProducer() = default;

const std::string& ResidualProducer::path() const { return impl_->files.front()->path(); }
const ResidualHeader& ResidualProducer::header() const { return impl_->files.front()->header(); }
int ResidualProducer::tileSize() const { return impl_->tileSize; }
int ResidualProducer::delta() const { return impl_->delta; }
int ResidualProducer::maxLevel() const { return impl_->maxLevel; }

bool ResidualProducer::hasTile(int level, int tx, int ty) const {
    if (level < 0) {
        return false;
    }
    // The root with delta > 0 folds file levels 0..delta (tile()).
    for (int l = level == 0 ? 0 : level + impl_->delta; l <= level + impl_->delta; ++l) {
        if (impl_->stored(l, tx, ty)) {
            return true;
        }
    }
    return false;
}

int ResidualProducer::tileSamples(int level) const {
    RelativeTile rel;
    const int k = deepestHolder(impl_->files, level + impl_->delta, 0, 0, rel);
    return k >= 0 ? impl_->files[static_cast<size_t>(k)]->header().tileSamples(rel.level) : impl_->tileSize + 5;
}

std::vector<float> ResidualProducer::tile(int level, int tx, int ty) const {
    const size_t stride = static_cast<size_t>(impl_->tileSize) + 5;
    const int whole = static_cast<int>(stride);
    std::vector<float> out(stride * stride);
    if (level != 0 || impl_->delta == 0) {
        impl_->load(level + impl_->delta, tx, ty, 0, 0, whole, out.data(), stride);
        return out;
    }
    std::vector<float> other;
    return std::move(impl_->root(out, other));
}

ResidualWindow ResidualProducer::storedWindow(int level, int tx, int ty, int x0, int y0, int side) const {
    if (level == 0 && impl_->delta > 0) {
        fail(path(), "the root of a producer with delta > 0 folds several levels: it has no stored window");
    }
    int samples = 0;
    return impl_->stored(level + impl_->delta, tx, ty, x0, y0, side, samples);
}

void ResidualProducer::window(int level, int tx, int ty, int x0, int y0, int side, float* out, size_t outStride) const {
    if (level != 0 || impl_->delta == 0) {
        impl_->load(level + impl_->delta, tx, ty, x0, y0, side, out, outStride);
        return;
    }
    // The root's window, composed in this thread's two planes, which stay for its next root when
    // tiles are up to 512 samples (2 MB at most); larger ones get planes of their own.
    thread_local std::vector<float> keptA, keptB;
    std::vector<float> ownA, ownB;
    const bool keep = impl_->tileSize <= 512;
    const std::vector<float>& root = keep ? impl_->root(keptA, keptB) : impl_->root(ownA, ownB);
    const size_t stride = static_cast<size_t>(impl_->tileSize) + 5;
    for (int j = 0; j < side; ++j) {
        std::copy_n(&root[static_cast<size_t>(x0) + (static_cast<size_t>(y0) + static_cast<size_t>(j)) * stride],
                    side, out + static_cast<size_t>(j) * outStride);
    }
}

} // namespace pyramid
