// What versions 2 and 3 of the context-coded residual tile (doc/format.md 1.8) keep while coding
// a tile: the planes of the samples coded so far, and what one sample's coding depends on.
// Internal to formats/residual_context_v2.cpp and formats/residual_context_parent.hpp.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "formats/residual_context_models.hpp"

namespace pyramid::context_coding {

// Version 3's predictions are held within +-kPredictionLimit.
inline constexpr int64_t kPredictionLimit = 65536;
// Sign models: the grid place (4) x the left and lower values' signs (3 x 3) x the prediction's
// sign (3) x the magnitude's class (3), per set of tables.
inline constexpr size_t kSignContexts = 4 * 27 * 3;

inline int signOf(int64_t v) { return (v > 0) - (v < 0); }

inline int32_t limitPrediction(int64_t p) {
    return static_cast<int32_t>(std::clamp(p, -kPredictionLimit, kPredictionLimit));
}

// The median predictor's rule; shadows reach +-(2^30 + 2^15), so in 64 bits.
inline int64_t median(int64_t a, int64_t b, int64_t c) {
    return c >= std::max(a, b) ? std::min(a, b) : (c <= std::min(a, b) ? std::max(a, b) : a + b - c);
}

// The tile's residuals, values and magnitudes so far, each in a plane with two columns of zeros
// on the left, three on the right and two rows below: a sample's neighbours outside the tile read
// 0, as the format says, without a test. The parent modes also keep the shadows and each
// predictor's errors, and mode 4 its clamped parent plane (0 outside the tile too).
struct Planes {
    int size;
    size_t stride;
    std::vector<int32_t> residual, value, shadow, clamped;
    std::vector<uint32_t> magnitude, gridError, shadowError;
    const int32_t* parent = nullptr; // the parent plane, size x size (modes 3 and 4)
    Planes(int size_, int mode)
        : size(size_), stride(static_cast<size_t>(size_) + 5), residual(stride * (static_cast<size_t>(size_) + 2)),
          value(residual.size()), shadow(mode >= 3 ? residual.size() : 0), clamped(mode == 4 ? residual.size() : 0),
          magnitude(residual.size()), gridError(shadow.size()), shadowError(shadow.size()) {}
    size_t at(int x, int y) const { return (static_cast<size_t>(y) + 2) * stride + static_cast<size_t>(x) + 2; }
    int32_t parentAt(int x, int y) const {
        return parent[static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)];
    }
};

// The planes of a tile, kept by the thread for its next tile of the same size: no cell of their
// borders is ever written, and every cell within the tile is written before any later sample
// reads it, so kept planes need no clearing, whatever kind of tile used them before (they are
// mode 4's, a superset of every kind's). Allocating and clearing them for every tile (seven
// planes of 160 KB at 192-tiles) took a third of the decoding's time. Tiles of more than
// kKeptPlanesSize samples a side get planes of their own, so that what a thread keeps stays
// under 8 MB.
inline constexpr int kKeptPlanesSize = 512;

class PlanesLease {
public:
    PlanesLease(int size, int mode) {
        if (size > kKeptPlanesSize) {
            own_ = std::make_unique<Planes>(size, mode);
            planes_ = own_.get();
            return;
        }
        thread_local std::unique_ptr<Planes> kept;
        if (!kept || kept->size != size) {
            kept = std::make_unique<Planes>(size, 4);
        }
        planes_ = kept.get();
        planes_->parent = nullptr;
    }
    PlanesLease(const PlanesLease&) = delete;
    PlanesLease& operator=(const PlanesLease&) = delete;
    Planes& operator*() const { return *planes_; }

private:
    std::unique_ptr<Planes> own_;
    Planes* planes_ = nullptr;
};

// What a sample's coding depends on, from the values coded before it.
struct Context {
    int32_t prediction = 0;
    size_t table = 0;
    size_t sign = 0;     // the sign model without the magnitude class
    int32_t grid = 0;    // modes 3 and 4: the grid predictor's and the shadow predictor's predictions
    int32_t fromShadow = 0;
    int step = -1;       // mode 4 at a step: the step flag's model (-1 elsewhere)
    int32_t low = 0;     // mode 4 at a step: either side's prediction
    int32_t high = 0;
    uint32_t activity = 0; // mode 4 at a step: the high side's activity
    size_t pattern = 0;    // the grid place and the left and lower values' signs
};

// The sign model of a value predicted by `p` with the tables of `set`.
inline size_t signModel(size_t pattern, int64_t p, size_t set) {
    return (pattern * 3 + static_cast<size_t>(signOf(p) + 1)) * 3 + set * kSignContexts;
}

} // namespace pyramid::context_coding
