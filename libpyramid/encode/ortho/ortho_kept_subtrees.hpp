// The subtrees of a build's first walk, kept for its second (ortho_build.cpp). A build with
// colour residuals beside TIFF or DXT tiles walks the subtrees twice: first for the TIFF and
// DXT tiles, then, once levels 0..C are rebuilt, for the colour residuals, which predict each
// subtree from them. When every subtree's true tiles fit in a budget, the first walk keeps them
// and the second encodes them again instead of sampling and reducing the input once more: the
// same tiles, so the same files. Memory: at most the budget, and each tile's pixels are let go
// as soon as its colour residual is encoded, so that the tiles encoded next reuse them.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "libpyramid/encode/ortho/ortho_item_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_levels.hpp"

namespace pyramid {

class KeptSubtrees {
public:
    // Keeps the `items` subtrees of a walk in `order` if their tiles take at most `budgetBytes`
    // (counted as if none were blank).
    KeptSubtrees(const OrthoLevels& levels, OrthoLevels::WalkOrder order, int64_t items, int64_t budgetBytes);

    bool active() const { return !kept_.empty(); }
    // From the first walk: subtree `index` (0..items-1), after its TIFF and DXT tiles.
    void keep(int64_t index, TileBatch&& item);
    // The second walk: each kept subtree encoded by `encoder` on `threads` threads and handed to
    // `hand` (index, item), in order of index as threads become free, as OrthoLevels::walk hands
    // out subtrees. `hand` returning false stops the walk; an item that fails calls `failed`
    // (index) on its thread before the error is rethrown, lowest index first. Returns `items`.
    int64_t encode(const OrthoItemEncoder& encoder, int threads, const std::function<bool(int64_t, EncodedItem&&)>& hand,
                   const std::function<void(int64_t)>& failed);

private:
    std::vector<TileBatch> kept_;
};

} // namespace pyramid
