// The parts of context-coded residual tiles (doc/format.md, 1.8) that every version shares: the
// constants, the adaptive frequency tables, version 1's initial counts, the zigzag code, the
// predictors of modes 1 and 2 and the activity of a sample's coded neighbours. Internal to
// formats/residual_context*.cpp.
#pragma once
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

namespace pyramid::context_coding {

// The codec's constants: part of the format. Changing any of them changes every blob.
inline constexpr uint32_t kDirect = 32;           // zigzag values 0..31 are symbols of their own
inline constexpr uint32_t kSymbols = kDirect + 1; // and symbol 32 escapes larger ones (versions 0, 1)
inline constexpr int kActivityBins = 14;
inline constexpr int kModels = kActivityBins * 4; // activity bin x the sample's grid parity
inline constexpr uint32_t kIncrement = 24;        // a symbol's count grows by this when coded
inline constexpr uint32_t kTotalLimit = 1u << 16; // counts are halved when their total passes it
inline constexpr size_t kHeaderBytes = 8;

// The geometric prior of the value tables (versions 1 and 2): theta / 256 per activity bin, and
// the prior's weight, in the fixed point of priorWeights.
inline constexpr std::array<uint32_t, kActivityBins> kTheta = {8,   96,  140, 160, 180, 200, 220,
                                                               232, 238, 240, 242, 242, 242, 242};
inline constexpr uint32_t kPriorWeight = 32;

// Mode 2's weights in 16ths per place in the upsampling grid: (x odd, y even), (x even, y odd),
// (x odd, y odd), over the residuals W, S, SW, SE, WW, SS.
inline constexpr int kPredictionWeights[3][6] = {
    // W   S  SW  SE  WW  SS
    {0, 5, -2, -2, -4, -1},
    {10, 0, -2, 2, -3, -3},
    {12, 6, 0, 0, -3, -2},
};

// An adaptive frequency table: counts start as the version says, grow by kIncrement when their
// symbol is coded, and are halved (rounding up) when their total passes kTotalLimit, so that
// every total stays within the coder's 16 bits.
template <uint32_t N>
struct Model {
    std::array<uint32_t, N> count;
    uint32_t total = N;
    Model() { count.fill(1); }
    void start(const std::array<uint32_t, N>& counts) {
        count = counts;
        total = 0;
        for (const uint32_t c : count) {
            total += c;
        }
    }
    void update(uint32_t s) {
        count[s] += kIncrement;
        total += kIncrement;
        if (total > kTotalLimit) {
            total = 0;
            for (uint32_t& c : count) {
                c = (c + 1) / 2;
                total += c;
            }
        }
    }
    uint32_t cumulative(uint32_t s) const {
        uint32_t sum = 0;
        for (uint32_t k = 0; k < s; ++k) {
            sum += count[k];
        }
        return sum;
    }
};

// kPriorWeight theta^m in 16.16 fixed point, m = 0..16, for value table `table` (theta = 0 for
// samples of even column and row, which copy their parent).
inline std::array<uint32_t, 17> priorWeights(int table) {
    const uint32_t theta = table % 4 == 0 ? 0 : kTheta[static_cast<size_t>(table / 4)];
    std::array<uint32_t, 17> weight{};
    weight[0] = kPriorWeight << 16;
    for (size_t m = 1; m < weight.size(); ++m) {
        weight[m] = (weight[m - 1] * theta) >> 8;
    }
    return weight;
}

// Version 1's initial counts of value table `table`: symbol z starts at 1 + floor(w(m)) with
// m = ceil(z / 2) (16 for the escape).
inline std::array<uint32_t, kSymbols> initialCounts(int table) {
    const std::array<uint32_t, 17> weight = priorWeights(table);
    std::array<uint32_t, kSymbols> counts{};
    for (uint32_t z = 0; z < kSymbols; ++z) {
        const uint32_t m = z == kDirect ? 16 : (z + 1) / 2;
        counts[z] = 1 + (weight[m] >> 16);
    }
    return counts;
}

inline uint32_t zigzag(int32_t v) {
    return v >= 0 ? 2u * static_cast<uint32_t>(v) : 2u * static_cast<uint32_t>(-v) - 1u;
}
inline int32_t unzigzag(uint32_t z) {
    return (z & 1u) != 0 ? -static_cast<int32_t>((z + 1u) / 2u) : static_cast<int32_t>(z / 2u);
}

// The median predictor of a sample from its left (a), lower (b) and lower-left (c) neighbours
// in storage order; on the first row and column the missing ones are taken as doc/format.md
// says: a = b on the first column, b = c = a on the first row, and 0 for the first sample.
inline int32_t medianPrediction(const int32_t* r, int x, int y, int size) {
    const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
    const auto s = static_cast<size_t>(size);
    const int32_t a = x > 0 ? r[i - 1] : (y > 0 ? r[i - s] : 0);
    const int32_t b = y > 0 ? r[i - s] : a;
    const int32_t c = x > 0 && y > 0 ? r[i - s - 1] : a;
    if (c >= std::max(a, b)) {
        return std::min(a, b);
    }
    if (c <= std::min(a, b)) {
        return std::max(a, b);
    }
    return a + b - c;
}

// Mode 2's prediction: residuals outside the tile are 0; the weighted sum in 16ths, rounded by
// (sum + 8) >> 4 (an arithmetic shift: floor). Samples of even column and row are predicted as 0.
inline int32_t gridPrediction(const int32_t* r, int x, int y, int size) {
    const int parity = (x & 1) + 2 * (y & 1);
    if (parity == 0) {
        return 0;
    }
    const int* w = kPredictionWeights[parity - 1];
    const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
    const auto s = static_cast<size_t>(size);
    int32_t sum = 0;
    if (x > 0) {
        sum += w[0] * r[i - 1] + (y > 0 ? w[2] * r[i - s - 1] : 0);
    }
    if (y > 0) {
        sum += w[1] * r[i - s] + (x + 1 < size ? w[3] * r[i - s + 1] : 0);
    }
    if (x > 1) {
        sum += w[4] * r[i - 2];
    }
    if (y > 1) {
        sum += w[5] * r[i - 2 * s];
    }
    return (sum + 8) >> 4;
}

inline int32_t prediction(int mode, const int32_t* r, int x, int y, int size) {
    if (mode == 0) {
        return 0;
    }
    return mode == 1 ? medianPrediction(r, x, y, size) : gridPrediction(r, x, y, size);
}

// The activity of the values already coded around a sample: left and lower twice, lower-left and
// lower-right once, and from version 1 on two left and two below once; 0 outside the tile.
template <int Version>
[[gnu::always_inline]] inline uint32_t activityOf(const uint32_t* magnitude, int x, int y, int size) {
    const size_t i = static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x);
    const auto s = static_cast<size_t>(size);
    const uint32_t w = x > 0 ? magnitude[i - 1] : 0;
    const uint32_t south = y > 0 ? magnitude[i - s] : 0;
    const uint32_t sw = x > 0 && y > 0 ? magnitude[i - s - 1] : 0;
    const uint32_t se = y > 0 && x + 1 < size ? magnitude[i - s + 1] : 0;
    uint32_t activity = 2 * w + 2 * south + sw + se;
    if constexpr (Version >= 1) {
        activity += (x > 1 ? magnitude[i - 2] : 0) + (y > 1 ? magnitude[i - 2 * s] : 0);
    }
    return activity;
}

// The value table of a sample: the activity in bins of powers of two, and the sample's parity in
// the tile (even columns and rows copy the parent in the upsampling grid).
inline int tableOf(uint32_t activity, int x, int y) {
    const int bin = std::min(kActivityBins - 1, static_cast<int>(std::bit_width(activity)));
    return bin * 4 + (x & 1) + 2 * (y & 1);
}

} // namespace pyramid::context_coding
