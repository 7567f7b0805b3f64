// How versions 2 and 3 of the context-coded residual tile (doc/format.md 1.8) code one value: its
// magnitude from an activity table (symbols 0..15, 16 an escape: the escape's bit length from the
// escape tables, its top bits as binary decisions, the rest as equally likely bits), then its
// sign as a binary decision. The tables of one tile: version 2's set, or the parent modes' sets.
// Internal to formats/residual_context_v2.cpp and formats/residual_context_terraces.cpp.
#pragma once
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>

#include "formats/residual_context_models.hpp"
#include "formats/residual_context_parent.hpp"
#include "formats/residual_range_coder.hpp"

namespace pyramid::context_coding {

// Version 2's constants (doc/format.md, 1.8).
inline constexpr uint32_t kDirectMagnitudes = 16;             // magnitudes 0..15 are symbols of their own
inline constexpr uint32_t kMagnitudes = kDirectMagnitudes + 1; // and symbol 16 escapes larger ones
inline constexpr uint32_t kExponents = 17;                     // an escape's bit length - 1: 0..16
inline constexpr int kModelledBits = 4;                        // the top bits below an escape's leading one
inline constexpr size_t kPrefixes = size_t{1} << kModelledBits;
inline constexpr size_t kEscapeTables = kActivityBins / 2;

// Version 2's tables (one set), or version 3's (mode 3: three, the grid predictor, a flat
// neighbourhood, the shadow predictor chosen by past errors; mode 4: those and a step's low and
// high sides, and the step flags; mode 5: one).
template <size_t Sets>
struct Models {
    std::array<Model<kMagnitudes>, kModels * Sets> magnitudes;
    std::array<Model<kExponents>, kEscapeTables> exponents;
    std::array<BitModel, kEscapeTables * kExponents * kPrefixes> bits;
    std::array<BitModel, kSignContexts * Sets> signs;
    std::array<BitModel, Sets == 5 ? kStepContexts : 0> steps;
    Models() {
        static const std::array<std::array<uint32_t, kMagnitudes>, kModels> initial = [] {
            std::array<std::array<uint32_t, kMagnitudes>, kModels> t{};
            for (int k = 0; k < kModels; ++k) {
                const std::array<uint32_t, 17> weight = priorWeights(k);
                t[static_cast<size_t>(k)][0] = 1 + (weight[0] >> 16);
                for (size_t q = 1; q < kMagnitudes; ++q) {
                    t[static_cast<size_t>(k)][q] = 2 * (1 + (weight[q] >> 16));
                }
            }
            return t;
        }();
        for (size_t k = 0; k < magnitudes.size(); ++k) {
            magnitudes[k].start(initial[k % kModels]);
        }
    }
};

inline size_t magnitudeClass(uint32_t a) { return (a > 2 ? 1u : 0u) + (a > 8 ? 1u : 0u); }

template <uint32_t N>
[[gnu::always_inline]] inline uint32_t decodeSymbol(RangeDecoder& coder, Model<N>& m) {
    const uint32_t s = coder.decodeSymbol(m.count, m.total);
    m.update(s);
    return s;
}

// The `below` bits under the leading one of a number `u` of below + 1 bits (an escape's, a gap's in
// the terrace list): the top kModelledBits of them as binary decisions, each in model
// `bits[prefix]` (prefix: a 1 followed by the bits before it, so 1 to kPrefixes - 1), the rest
// as equally likely bits.
[[gnu::always_inline]] inline void encodeBelowLeadingOne(RangeEncoder& coder, BitModel* bits, uint32_t u, int below) {
    const int modelled = std::min(below, kModelledBits);
    size_t prefix = 1;
    for (int j = 0; j < modelled; ++j) {
        const int bit = static_cast<int>((u >> (below - 1 - j)) & 1u);
        coder.encodeBit(bits[prefix], bit);
        prefix = prefix * 2 + static_cast<size_t>(bit);
    }
    const int rest = below - modelled;
    coder.encodeBits(u & ((1u << rest) - 1u), rest);
}

// The number encodeBelowLeadingOne codes, with its leading one.
[[gnu::always_inline]] inline uint32_t decodeBelowLeadingOne(RangeDecoder& coder, BitModel* bits, int below) {
    const int modelled = std::min(below, kModelledBits);
    size_t prefix = 1;
    for (int j = 0; j < modelled; ++j) {
        prefix = prefix * 2 + static_cast<size_t>(coder.decodeBit(bits[prefix]));
    }
    const int rest = below - modelled;
    return (static_cast<uint32_t>(prefix) << rest) | coder.decodeBits(rest);
}

// Value `v` (|v| below 16 + 2^17 - 1) with magnitude table `table` and sign model `sign` (without
// the magnitude class).
template <size_t Sets>
[[gnu::always_inline]] inline void encodeValue(RangeEncoder& coder, Models<Sets>& models, size_t table, size_t sign,
                                               int32_t v) {
    const auto a = static_cast<uint32_t>(std::abs(v));
    Model<kMagnitudes>& m = models.magnitudes[table];
    const uint32_t symbol = std::min(a, kDirectMagnitudes);
    coder.encode(m.cumulative(symbol), m.count[symbol], m.total);
    m.update(symbol);
    if (symbol == kDirectMagnitudes) {
        const uint32_t e = a - kDirectMagnitudes + 1; // 1 .. 2^17 - 1
        const auto k = static_cast<uint32_t>(std::bit_width(e)) - 1;
        const size_t escapes = (table % kModels) / 8;
        Model<kExponents>& exponents = models.exponents[escapes];
        coder.encode(exponents.cumulative(k), exponents.count[k], exponents.total);
        exponents.update(k);
        encodeBelowLeadingOne(coder, &models.bits[(escapes * kExponents + k) * kPrefixes], e, static_cast<int>(k));
    }
    if (a != 0) {
        coder.encodeBit(models.signs[sign + magnitudeClass(a)], v < 0 ? 1 : 0);
    }
}

// The value encodeValue codes with the same tables.
template <size_t Sets>
[[gnu::always_inline]] inline int32_t decodeValue(RangeDecoder& coder, Models<Sets>& models, size_t table, size_t sign) {
    uint32_t a = decodeSymbol(coder, models.magnitudes[table]);
    if (a == kDirectMagnitudes) {
        const size_t escapes = (table % kModels) / 8;
        const uint32_t k = decodeSymbol(coder, models.exponents[escapes]);
        const uint32_t e = decodeBelowLeadingOne(coder, &models.bits[(escapes * kExponents + k) * kPrefixes],
                                                 static_cast<int>(k));
        a = kDirectMagnitudes + e - 1;
    }
    auto v = static_cast<int32_t>(a);
    if (a != 0) {
        const int32_t negative = coder.decodeBit(models.signs[sign + magnitudeClass(a)]);
        v = (v ^ -negative) + negative;
    }
    return v;
}

} // namespace pyramid::context_coding
