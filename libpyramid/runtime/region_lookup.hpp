// A producer's files: a main pyramid plus region files nested in it (doc/format.md, 1.4).
// A tile is served by the deepest file whose pyramid holds it.
#pragma once
#include <memory>
#include <vector>

namespace pyramid {

// The file's own coordinates of absolute tile (level, tx, ty).
struct RelativeTile {
    int level = 0, tx = 0, ty = 0;
};

// Index into `readers` of the deepest file holding absolute tile (level, tx, ty), or -1.
// Readers have header() with rootLevel, rootTx, rootTy, maxLevel and contains(level, tx, ty).
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
        const int x = tx - (h.rootTx << l);
        const int y = ty - (h.rootTy << l);
        if (h.contains(l, x, y)) {
            best = static_cast<int>(k);
            bestRoot = h.rootLevel;
            rel = RelativeTile{l, x, y};
        }
    }
    return best;
}

} // namespace pyramid
