// Version 3 of the context-coded residual tile (doc/format.md 1.8): the contexts of its two
// modes, predicted from the tile's parent plane and the shadows of the samples coded before.
// Mode 3, the parent mode: three sets of tables (the grid predictor, a flat neighbourhood, the
// shadow predictor chosen by past errors). Mode 4, the parent mode with steps: the grid
// predictor over the parent plane held within its parent samples' range, and at a step (the
// neighbours' shadows far apart) a flag for the side the sample lies on; five sets of tables.
// Internal to formats/residual_context_v2.cpp.
#pragma once
#include <array>
#include <cstdlib>
#include <span>

#include "formats/residual_context_state.hpp"

namespace pyramid::context_coding {

// A sample's neighbours' shadows within this of each other are flat; a shadow prediction must
// have done this much better than the grid predictor on the four nearest samples of the same
// place in the grid to be chosen where they are not; neighbours' shadows more than kStepSpread
// apart are a step (mode 4).
inline constexpr int32_t kFlatSpread = 1;
inline constexpr uint32_t kSwitchMargin = 32;
inline constexpr int64_t kStepSpread = 512;
// Step flags' models: how many of the four neighbours lie on the low side (5) x the grid place
// (4) x where the parent plane lies between the two sides (6).
inline constexpr size_t kStepContexts = 5 * 4 * 6;

// Mode 4's clamped parent plane: at each odd place of the grid, the parent plane held within
// the range of the parent samples it is interpolated between (the plane's values at the nearest
// even places, those within the tile); at even places the parent plane itself.
inline void clampParentPlane(Planes& planes) {
    const int n = planes.size;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            int64_t lo = planes.parentAt(x, y), hi = lo;
            const auto take = [&](int u, int v) {
                if (u < n && v < n) {
                    lo = std::min<int64_t>(lo, planes.parentAt(u, v));
                    hi = std::max<int64_t>(hi, planes.parentAt(u, v));
                }
            };
            const bool oddX = (x & 1) != 0, oddY = (y & 1) != 0;
            if (oddX || oddY) {
                lo = INT64_MAX;
                hi = INT64_MIN;
                const int x0 = oddX ? x - 1 : x, y0 = oddY ? y - 1 : y;
                take(x0, y0);
                take(oddX ? x + 1 : x, y0);
                take(x0, oddY ? y + 1 : y);
                take(oddX ? x + 1 : x, oddY ? y + 1 : y);
            }
            planes.clamped[planes.at(x, y)] = static_cast<int32_t>(std::clamp<int64_t>(planes.parentAt(x, y), lo, hi));
        }
    }
}

// Mode 4's grid prediction: the clamped plane less the parent plane, plus mode 2's weights over
// the neighbours' shadows less their clamped plane.
[[gnu::always_inline]] inline int32_t clampedGridPrediction(const Planes& planes, size_t i, int x, int y, int parity) {
    const int64_t g = planes.parentAt(x, y);
    const int64_t c = planes.clamped[i];
    if (parity == 0) {
        return limitPrediction(c - g);
    }
    const size_t s = planes.stride;
    const auto d = [&](size_t k) { return static_cast<int64_t>(planes.shadow[k]) - planes.clamped[k]; };
    const int* w = kPredictionWeights[parity - 1];
    const int64_t sum = w[0] * d(i - 1) + w[1] * d(i - s) + w[2] * d(i - s - 1) + w[3] * d(i - s + 1) + w[4] * d(i - 2) +
                        w[5] * d(i - 2 * s);
    return limitPrediction(c - g + ((sum + 8) >> 4));
}

// Modes 3 and 4: the shadow predictor (the median predictor over the neighbours' shadows, less
// the sample's parent plane) and the set of tables it codes with; `grid` is the mode's grid
// prediction, `activity` version 2's over the neighbours' magnitudes.
template <int Mode>
[[gnu::always_inline]] inline Context parentContext(const Planes& planes, size_t i, int x, int y, int32_t grid,
                                                   uint32_t activity) {
    const size_t s = planes.stride;
    const int32_t* h = planes.shadow.data();
    const int64_t g = planes.parentAt(x, y);
    int64_t w = h[i - 1], south = h[i - s], sw = h[i - s - 1], se = h[i - s + 1];
    if (x == 0) {
        w = sw = south;
    }
    if (y == 0) {
        south = sw = se = w;
    }
    if (x + 1 == planes.size) {
        se = south;
    }
    if (x == 0 && y == 0) {
        w = south = sw = se = g;
    }
    Context c;
    c.grid = grid;
    c.fromShadow = limitPrediction(median(w, south, sw) - g);
    const int parity = (x & 1) + 2 * (y & 1);
    c.pattern = static_cast<size_t>((parity * 3 + signOf(planes.value[i - 1]) + 1) * 3 + signOf(planes.value[i - s]) + 1);
    const uint32_t disagreement = 2 * static_cast<uint32_t>(std::abs(c.fromShadow - grid));
    const int64_t lo = std::min(std::min(w, south), std::min(sw, se));
    const int64_t hi = std::max(std::max(w, south), std::max(sw, se));
    size_t set = 0;
    int32_t p = grid;
    if (x > 0 && y > 0 && x + 1 < planes.size && hi - lo <= kFlatSpread) {
        set = 1;
        p = c.fromShadow;
    } else if (Mode == 4 && x > 0 && y > 0 && hi - lo > kStepSpread) {
        const int64_t mid = lo + ((hi - lo) >> 1);
        const auto isLow = [mid](int64_t v) { return v <= mid; };
        const int64_t lowSide = isLow(w) ? w : (isLow(south) ? south : lo);
        const int64_t highSide = !isLow(w) ? w : (!isLow(south) ? south : hi);
        const auto high = [&](int64_t v) { return isLow(v) ? highSide : v; };
        const int lows = isLow(w) + isLow(south) + isLow(sw) + isLow(se);
        const int64_t between = g < lo ? 0 : 1 + std::min<int64_t>(4, (g - lo) * 4 / (hi - lo));
        c.step = static_cast<int>(((lows * 4 + parity) * 6) + between);
        c.low = limitPrediction(lowSide - g);
        c.high = limitPrediction(median(high(w), high(south), high(sw)) - g);
        c.activity = activity + disagreement;
        return c;
    } else {
        const auto past = [&](const std::vector<uint32_t>& e) {
            return e[i - 2] + e[i - 2 * s] + e[i - 2 * s - 2] + e[i - 2 * s + 2];
        };
        if (past(planes.shadowError) + kSwitchMargin < past(planes.gridError)) {
            set = 2;
            p = c.fromShadow;
        }
    }
    if (set != 1) {
        activity += static_cast<uint32_t>(std::abs(p));
    }
    activity += disagreement;
    c.prediction = p;
    c.table = static_cast<size_t>(tableOf(activity, x, y)) + set * kModels;
    c.sign = signModel(c.pattern, p, set);
    return c;
}

// Mode 4 at a step, once its flag is known: the low side (set 3, the activity 0) or the high side
// (set 4).
inline void resolveStep(Context& c, int high, int x, int y) {
    const size_t set = high != 0 ? 4 : 3;
    c.prediction = high != 0 ? c.high : c.low;
    c.table = static_cast<size_t>(tableOf(high != 0 ? c.activity : 0, x, y)) + set * kModels;
    c.sign = signModel(c.pattern, c.prediction, set);
}

// Modes 3 and 4 keep each sample's shadow and both predictors' errors for the samples after it.
[[gnu::always_inline]] inline void keepParentState(Planes& planes, size_t i, int x, int y, int32_t residual,
                                                   const Context& c) {
    planes.shadow[i] = planes.parentAt(x, y) + residual;
    planes.gridError[i] = static_cast<uint32_t>(std::abs(residual - c.grid));
    planes.shadowError[i] = static_cast<uint32_t>(std::abs(residual - c.fromShadow));
}

// Whether mode 4 is worth trying on a tile: whether it has a step whose low side is flat (at
// least two of the four neighbours on the low side, within kFlatSpread of each other), as where
// land meets the sea. Elsewhere mode 3 is nearly always the smaller, and this saves coding the
// tile twice.
inline bool hasShoreSteps(std::span<const int16_t> residuals, int size, std::span<const int32_t> parent) {
    const auto n = static_cast<size_t>(size);
    const auto h = [&](size_t x, size_t y) { return static_cast<int64_t>(parent[y * n + x]) + residuals[y * n + x]; };
    for (size_t y = 1; y < n; ++y) {
        for (size_t x = 1; x < n; ++x) {
            const std::array<int64_t, 4> around = {h(x - 1, y), h(x, y - 1), h(x - 1, y - 1),
                                                   x + 1 < n ? h(x + 1, y - 1) : h(x, y - 1)};
            const auto [lo, hi] = std::minmax_element(around.begin(), around.end());
            if (*hi - *lo <= kStepSpread) {
                continue;
            }
            const int64_t mid = *lo + ((*hi - *lo) >> 1);
            int lows = 0;
            int64_t lowest = INT64_MAX, highest = INT64_MIN;
            for (const int64_t v : around) {
                if (v <= mid) {
                    ++lows;
                    lowest = std::min(lowest, v);
                    highest = std::max(highest, v);
                }
            }
            if (lows >= 2 && highest - lowest <= kFlatSpread) {
                return true;
            }
        }
    }
    return false;
}

} // namespace pyramid::context_coding
