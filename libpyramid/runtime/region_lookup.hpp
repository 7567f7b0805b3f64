// A producer's files: a main pyramid plus region files nested in it (doc/format.md, 1.4).
// A tile is served by the deepest file whose pyramid holds it.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

namespace pyramid {

// The file's own coordinates of absolute tile (level, tx, ty).
struct RelativeTile {
    int level = 0, tx = 0, ty = 0;
};

// Index into `readers` of the deepest file holding absolute tile (level, tx, ty), or -1.
// Readers have header() with rootLevel, rootTx, rootTy, maxLevel (at most 30, as validated)
// and contains(level, tx, ty). A file's root at `level` lies at (rootTx << l, rootTy << l),
// which passes 2^31 for deep levels: it is computed in 64 bits.
template <class Reader>
int deepestHolder(const std::vector<std::unique_ptr<Reader>>& readers, int level, int tx, int ty, RelativeTile& rel) {
    int best = -1;
    int bestRoot = -1;
    for (size_t k = 0; k < readers.size(); ++k) {
        const auto& h = readers[k]->header();
        const int l = level - h.rootLevel;
        if (l < 0 || l > h.maxLevel || h.rootLevel <= bestRoot) {
            continue;
        }
        const int64_t x = int64_t{tx} - (int64_t{h.rootTx} << l);
        const int64_t y = int64_t{ty} - (int64_t{h.rootTy} << l);
        if (x < 0 || y < 0 || x >= (int64_t{1} << l) || y >= (int64_t{1} << l)) {
            continue; // outside the file's root tile (and beyond int when far outside)
        }
        if (h.contains(l, static_cast<int>(x), static_cast<int>(y))) {
            best = static_cast<int>(k);
            bestRoot = h.rootLevel;
            rel = RelativeTile{l, static_cast<int>(x), static_cast<int>(y)};
        }
    }
    return best;
}

// Whether `reader` stores its relative tile `rel` (a tile it holds): a file may leave a tile out
// as an empty byte range (doc/format.md), and where the deepest file holding a tile leaves it out
// a residual set has zero residuals and an ortho set no tile, as beyond every file. The one rule
// for every producer, CPU and GL: ResidualProducer::hasTile and OrthoProducer::hasTile.
template <class Reader>
bool storesTile(const Reader& reader, const RelativeTile& rel) {
    return reader.tileRange(rel.level, rel.tx, rel.ty).size() > 0;
}

// deepestHolder, but -1 also when that file leaves the tile out (storesTile).
template <class Reader>
int deepestStorer(const std::vector<std::unique_ptr<Reader>>& readers, int level, int tx, int ty, RelativeTile& rel) {
    const int k = deepestHolder(readers, level, tx, ty, rel);
    return k >= 0 && storesTile(*readers[static_cast<size_t>(k)], rel) ? k : -1;
}

} // namespace pyramid
