#include "formats/dxt_solid_pairs.hpp"

#include <cstdlib>

namespace pyramid {

namespace {

constexpr int expand5(int q) { return (q << 3) | (q >> 2); }
constexpr int expand6(int q) { return (q << 2) | (q >> 4); }

// Built from the colours the pairs can make: for each colour c, the pair making it
// with the closest endpoints (the first in (a, b) order of those); then for each value, the
// closest colour, equally close ones by their pair's endpoints, then order. The same table as
// trying every pair for every value, in 256 x 256 steps instead of 256 x 4096.
template <int Bits>
std::array<SolidPair, 256> solidPairs() {
    constexpr int n = 1 << Bits;
    const auto expand = [](int q) { return Bits == 5 ? expand5(q) : expand6(q); };
    std::array<int, 256> spread{}, order{}; // per colour; spread -1: no pair makes it
    spread.fill(-1);
    for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
            const int ea = expand(a), eb = expand(b);
            const auto c = static_cast<size_t>((2 * ea + eb) / 3);
            const int s = std::abs(ea - eb);
            if (spread[c] < 0 || s < spread[c]) {
                spread[c] = s;
                order[c] = a * n + b;
            }
        }
    }
    std::array<SolidPair, 256> table{};
    for (int v = 0; v < 256; ++v) {
        int best = 1 << 30, pair = 0;
        for (int c = 0; c < 256; ++c) {
            const auto k = static_cast<size_t>(c);
            if (spread[k] < 0) {
                continue;
            }
            const int cost = std::abs(c - v) * 256 + spread[k];
            if (cost < best || (cost == best && order[k] < pair)) {
                best = cost;
                pair = order[k];
            }
        }
        table[static_cast<size_t>(v)] = {static_cast<uint8_t>(pair / n), static_cast<uint8_t>(pair % n)};
    }
    return table;
}

} // namespace

SolidTables::SolidTables() : five(solidPairs<5>()), six(solidPairs<6>()) {}

const SolidTables& solidTables() {
    static const SolidTables tables;
    return tables;
}

} // namespace pyramid
