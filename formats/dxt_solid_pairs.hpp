// The DXT colour fit's answer for blocks of one colour (dxt_colour_fit.hpp, candidate (b)): for
// each 8-bit value, the endpoints (a, b) of 5 or 6 bits whose colour at index 2,
// (2 E(a) + E(b)) / 3 with E the widening by bit replication, is closest to it; of equally
// close pairs, the one with the closest endpoints (then the lowest a and b).
#pragma once
#include <array>
#include <cstdint>

namespace pyramid {

struct SolidPair {
    uint8_t a = 0, b = 0;
};

struct SolidTables {
    SolidTables();
    std::array<SolidPair, 256> five; // 5-bit endpoints (red, blue)
    std::array<SolidPair, 256> six;  // 6-bit endpoints (green)
};

// Built on first use, so that programs which never write DXT do not build them at start-up.
const SolidTables& solidTables();

} // namespace pyramid
