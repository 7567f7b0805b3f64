#include "libpyramid/encode/ortho/ortho_kept_subtrees.hpp"

#include "libpyramid/support/parallel.hpp"

namespace pyramid {

KeptSubtrees::KeptSubtrees(const OrthoLevels& levels, OrthoLevels::WalkOrder order, int64_t items,
                           int64_t budgetBytes) {
    const int depth = levels.maxLevel() - levels.topLevels(order); // levels C + 1..M
    if (items <= 0 || budgetBytes <= 0 || depth >= 16) {
        return;
    }
    const int64_t tiles = ((int64_t{1} << (2 * depth)) - 1) / 3;
    const int64_t side = levels.tileSize() + 4;
    const int64_t itemBytes = tiles * side * side * levels.channels(); // tiles < 2^30: no overflow
    if (items <= budgetBytes / itemBytes) {
        kept_.resize(static_cast<size_t>(items));
    }
}

void KeptSubtrees::keep(int64_t index, TileBatch&& item) {
    kept_.at(static_cast<size_t>(index)) = std::move(item);
}

int64_t KeptSubtrees::encode(const OrthoItemEncoder& encoder, int threads,
                             const std::function<bool(int64_t, EncodedItem&&)>& hand,
                             const std::function<void(int64_t)>& failed) {
    const auto items = static_cast<int64_t>(kept_.size());
    std::atomic<bool> stop{false};
    parallelFor(items, threads, [&](int64_t i) {
        if (stop.load(std::memory_order_relaxed)) {
            return;
        }
        TileBatch& item = kept_[static_cast<size_t>(i)];
        try {
            EncodedItem encoded = encoder.encodeSubtree(std::move(item));
            item = TileBatch();
            if (!hand(i, std::move(encoded))) {
                stop = true;
            }
        } catch (...) {
            stop = true;
            failed(i);
            throw;
        }
    });
    kept_.clear();
    return items;
}

} // namespace pyramid
