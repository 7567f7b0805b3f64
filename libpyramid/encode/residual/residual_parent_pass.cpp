#include "libpyramid/encode/residual/residual_parent_pass.hpp"

#include <algorithm>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "formats/residual_codec.hpp"
#include "formats/residual_context.hpp"
#include "formats/residual_shadow.hpp"
#include "libpyramid/input/scratch_file.hpp"
#include "libpyramid/support/parallel.hpp"

namespace pyramid {

namespace {

// The blobs the pass chose, in a scratch file (input/scratch_file.hpp) that goes with it; any
// thread may add one.
class BlobSpool {
public:
    explicit BlobSpool(const std::string& where) : file_(where) {}

    void put(int64_t index, const std::vector<uint8_t>& blob) {
        uint64_t at = 0;
        {
            const std::lock_guard lock(mutex_);
            at = end_;
            end_ += blob.size();
            kept_[index] = {at, blob.size()};
        }
        file_.write(at, blob.data(), blob.size());
    }
    // Once every put is done.
    bool holds(int64_t index) const { return kept_.count(index) != 0; }
    std::vector<uint8_t> get(int64_t index) const {
        const auto [at, size] = kept_.at(index);
        std::vector<uint8_t> blob(size);
        file_.read(at, blob.data(), size);
        return blob;
    }

private:
    ScratchFile file_;
    std::mutex mutex_;
    uint64_t end_ = 0;
    std::unordered_map<int64_t, std::pair<uint64_t, size_t>> kept_;
};

struct Pass {
    const ResidualFileReader& reader;
    const ResidualHeader& h;
    std::unordered_map<uint64_t, int> uses; // tiles per stored byte range
    BlobSpool spool;

    // Tile (level, tx, ty), given its parent plane: its parent-mode blob where smaller; its shadow.
    std::vector<int32_t> code(int level, int tx, int ty, const std::vector<int32_t>& plane) {
        const int size = h.tileSamples(level);
        const std::vector<uint8_t> blob = reader.readTileBytes(level, tx, ty);
        std::vector<int16_t> residuals(static_cast<size_t>(size) * static_cast<size_t>(size));
        decodeResidualBlobInto(blob, size, reader.path(), residuals, plane);
        if (isContextResidualBlob(blob) && !contextBlobNeedsParent(blob) &&
            uses.at(reader.tileRange(level, tx, ty).begin) == 1 &&
            std::any_of(residuals.begin(), residuals.end(), [](int16_t r) { return r != 0; })) {
            const std::vector<uint8_t> other = encodeContextParentMode(residuals, size, plane);
            if (other.size() < blob.size()) {
                spool.put(h.tileIndex(level, tx, ty), other);
            }
        }
        return shadowOf(plane, residuals);
    }

    // The parent plane of child (level + 1, cx, cy) of a tile whose shadow is `shadow`.
    std::vector<int32_t> childPlane(int level, const std::vector<int32_t>& shadow, int cx, int cy) const {
        const ShadowParent p = shadowParentOf(h, level + 1, cx, cy);
        return upsampleShadow(shadow, h.tileSamples(level), h.tileSamples(level + 1), p.px, p.py);
    }

    int children(int level) const { return level + 1 <= h.minLevel ? 1 : 4; }
    static int childX(int tx, int c, int n) { return n == 1 ? 0 : 2 * tx + (c & 1); }
    static int childY(int ty, int c, int n) { return n == 1 ? 0 : 2 * ty + (c >> 1); }

    // The subtree rooted at (level, tx, ty).
    void visit(int level, int tx, int ty, const std::vector<int32_t>& plane) {
        const std::vector<int32_t> shadow = code(level, tx, ty, plane);
        if (level == h.maxLevel) {
            return;
        }
        const int n = children(level);
        for (int c = 0; c < n; ++c) {
            const int cx = childX(tx, c, n), cy = childY(ty, c, n);
            visit(level + 1, cx, cy, childPlane(level, shadow, cx, cy));
        }
    }
};

struct Subtree {
    int level, tx, ty;
    std::vector<int32_t> plane;
};

} // namespace

std::unique_ptr<ResidualFileWriter> rewriteInParentMode(const std::string& input, const std::string& output,
                                                        int threads) {
    const int workers = workerThreads(threads);
    const std::unique_ptr<ResidualFileReader> reader = ResidualFileReader::open(input);
    const ResidualHeader& h = reader->header();
    struct Tile {
        int level, tx, ty;
        uint64_t begin;
    };
    std::vector<Tile> tiles;
    Pass pass{*reader, h, {}, BlobSpool(input)};
    for (int l = 0; l <= h.maxLevel; ++l) {
        for (int ty = 0; ty < h.tilesPerSide(l); ++ty) {
            for (int tx = 0; tx < h.tilesPerSide(l); ++tx) {
                const uint64_t begin = reader->tileRange(l, tx, ty).begin;
                tiles.push_back({l, tx, ty, begin});
                ++pass.uses[begin];
            }
        }
    }
    // The top levels one after the other, until a level has subtrees enough for every thread.
    const int rootSize = h.tileSamples(0);
    std::vector<Subtree> level{{0, 0, 0, std::vector<int32_t>(static_cast<size_t>(rootSize) * static_cast<size_t>(rootSize), 0)}};
    while (level.front().level < h.maxLevel && level.size() < 4 * static_cast<size_t>(workers)) {
        std::vector<Subtree> below;
        for (const Subtree& t : level) {
            const std::vector<int32_t> shadow = pass.code(t.level, t.tx, t.ty, t.plane);
            const int n = pass.children(t.level);
            for (int c = 0; c < n; ++c) {
                const int cx = Pass::childX(t.tx, c, n), cy = Pass::childY(t.ty, c, n);
                below.push_back({t.level + 1, cx, cy, pass.childPlane(t.level, shadow, cx, cy)});
            }
        }
        level = std::move(below);
    }
    parallelFor(static_cast<int64_t>(level.size()), workers, [&](int64_t k) {
        Subtree& t = level[static_cast<size_t>(k)];
        pass.visit(t.level, t.tx, t.ty, t.plane);
        t.plane = {};
    });
    // The input's order: the stored bytes' order, then the tiles' (those sharing bytes).
    std::stable_sort(tiles.begin(), tiles.end(), [](const Tile& a, const Tile& b) { return a.begin < b.begin; });
    auto writer = std::make_unique<ResidualFileWriter>(output, h);
    for (const Tile& t : tiles) {
        const int64_t index = h.tileIndex(t.level, t.tx, t.ty);
        writer->writeTileBytes(t.level, t.tx, t.ty,
                               pass.spool.holds(index) ? pass.spool.get(index) : reader->readTileBytes(t.level, t.tx, t.ty));
    }
    writer->finish();
    return writer;
}

} // namespace pyramid
