#include "libpyramid/residual_producer.hpp"

#include <algorithm>

#include "formats/error.hpp"
#include "libpyramid/elevation_upsample.hpp"

namespace pyramid {

namespace {

// One file of the producer and where its pyramid sits in the absolute quadtree.
struct PyramidSource {
    std::unique_ptr<ResidualFileReader> reader;
    float scale = 1.0f; // file scale x producer scale, one float32 rounding

    // The file's own coordinates of absolute tile (level, tx, ty), if the file holds it.
    bool locate(int level, int tx, int ty, int& relLevel, int& relTx, int& relTy) const {
        const ResidualHeader& h = reader->header();
        relLevel = level - h.rootLevel;
        if (relLevel < 0 || relLevel > h.maxLevel) {
            return false;
        }
        relTx = tx - (h.rootTx << relLevel);
        relTy = ty - (h.rootTy << relLevel);
        return h.contains(relLevel, relTx, relTy);
    }
};

} // namespace

struct ResidualProducer::Impl {
    std::vector<PyramidSource> files; // main file first
    int delta = 0;
    int tileSize = 0;
    int maxLevel = 0;

    // The deepest file holding absolute tile (level, tx, ty); regions are more detailed than
    // the pyramids they nest in, so a deeper root wins.
    const PyramidSource* find(int level, int tx, int ty, int& rl, int& rx, int& ry) const {
        const PyramidSource* best = nullptr;
        int bestRoot = -1;
        for (const PyramidSource& f : files) {
            int l = 0, x = 0, y = 0;
            if (f.locate(level, tx, ty, l, x, y) && f.reader->header().rootLevel > bestRoot) {
                best = &f;
                bestRoot = f.reader->header().rootLevel;
                rl = l;
                rx = x;
                ry = y;
            }
        }
        return best;
    }

    // Scaled residuals of absolute file tile (level, tx, ty) into `out` (stride `stride`,
    // lower-left corner); returns the samples per side.
    int load(int level, int tx, int ty, float* out, size_t stride) const {
        int rl = 0, rx = 0, ry = 0;
        const PyramidSource* f = find(level, tx, ty, rl, rx, ry);
        if (!f) {
            fail(files.front().reader->path(), "no residual tile (" + std::to_string(level) + "," +
                                                   std::to_string(tx) + "," + std::to_string(ty) + ") in any file");
        }
        const std::vector<int16_t> r = f->reader->readTile(rl, rx, ry);
        const int s = f->reader->header().tileSamples(rl);
        for (int j = 0; j < s; ++j) {
            for (int i = 0; i < s; ++i) {
                out[static_cast<size_t>(i) + static_cast<size_t>(j) * stride] =
                    static_cast<float>(r[static_cast<size_t>(i + j * s)]) * f->scale;
            }
        }
        return s;
    }
};

ResidualProducer::ResidualProducer(const std::string& mainFile, const std::vector<std::string>& regions,
                                   const ResidualProducerOptions& options)
    : impl_(std::make_unique<Impl>()) {
    auto addFile = [&](const std::string& path) {
        PyramidSource f;
        f.reader = ResidualFileReader::open(path);
        f.scale = f.reader->header().scale * options.scale;
        impl_->files.push_back(std::move(f));
    };
    addFile(mainFile);
    const ResidualHeader& main = impl_->files.front().reader->header();
    if (main.rootLevel != 0) {
        fail(mainFile, "the main file of a residual producer must be rooted at tile (0,0,0)");
    }
    for (const std::string& region : regions) {
        addFile(region);
        const ResidualHeader& h = impl_->files.back().reader->header();
        if (h.tileSize != main.tileSize) {
            fail(region, "region tileSize " + std::to_string(h.tileSize) + " differs from the main file's " +
                             std::to_string(main.tileSize));
        }
        if (h.rootLevel < std::max(1, main.minLevel)) {
            fail(region, "a region file must be rooted at level 1 or deeper, and not above the main file's "
                         "minLevel (" + std::to_string(main.minLevel) + ")");
        }
    }
    if (options.delta < 0 || options.delta > main.minLevel) {
        fail(mainFile, "delta " + std::to_string(options.delta) + " is outside 0.." + std::to_string(main.minLevel));
    }
    impl_->delta = options.delta;
    impl_->tileSize = main.tileSize;
    for (const PyramidSource& f : impl_->files) {
        impl_->maxLevel = std::max(impl_->maxLevel, f.reader->header().rootLevel + f.reader->header().maxLevel);
    }
    impl_->maxLevel -= impl_->delta;
}

ResidualProducer::~ResidualProducer() = default;

const ResidualHeader& ResidualProducer::header() const { return impl_->files.front().reader->header(); }
int ResidualProducer::tileSize() const { return impl_->tileSize; }
int ResidualProducer::delta() const { return impl_->delta; }
int ResidualProducer::maxLevel() const { return impl_->maxLevel; }

bool ResidualProducer::hasTile(int level, int tx, int ty) const {
    int rl = 0, rx = 0, ry = 0;
    return level >= 0 && impl_->find(level + impl_->delta, tx, ty, rl, rx, ry) != nullptr;
}

int ResidualProducer::tileSamples(int level) const {
    int rl = 0, rx = 0, ry = 0;
    const int fileLevel = level + impl_->delta;
    const PyramidSource* f = impl_->find(fileLevel, 0, 0, rl, rx, ry);
    return f ? f->reader->header().tileSamples(rl) : impl_->tileSize + 5;
}

std::vector<float> ResidualProducer::tile(int level, int tx, int ty) const {
    const size_t stride = static_cast<size_t>(impl_->tileSize) + 5;
    std::vector<float> out(stride * stride, 0.0f);
    if (level != 0 || impl_->delta == 0) {
        impl_->load(level + impl_->delta, tx, ty, out.data(), stride);
        return out;
    }
    // Root with delta > 0: the upsample-and-add of file levels 0..delta, each a whole-tile 2x
    // upsample (all these levels are at or below minLevel, one tile each).
    std::vector<float> parent(stride * stride, 0.0f);
    impl_->load(0, 0, 0, parent.data(), stride);
    for (int l = 1; l <= impl_->delta; ++l) {
        std::fill(out.begin(), out.end(), 0.0f);
        const int s = impl_->load(l, 0, 0, out.data(), stride);
        upsampleAndAdd(parent.data(), stride, s - 5, 1, 1, out.data(), stride);
        std::swap(parent, out);
    }
    return parent;
}

} // namespace pyramid
