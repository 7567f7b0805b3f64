// Z (Lebesgue, Morton) order of the tiles of one quadtree level: index bit 2k is bit k of tx,
// bit 2k+1 is bit k of ty, so children follow (2tx,2ty), (2tx+1,2ty), (2tx,2ty+1), (2tx+1,2ty+1),
// the order in which the original tools store each level.
#pragma once
#include <cstdint>
#include <utility>

namespace pyramid {

inline std::pair<uint32_t, uint32_t> mortonDecode(uint64_t m) {
    auto compact = [](uint64_t v) {
        v &= 0x5555555555555555ull;
        v = (v | (v >> 1)) & 0x3333333333333333ull;
        v = (v | (v >> 2)) & 0x0F0F0F0F0F0F0F0Full;
        v = (v | (v >> 4)) & 0x00FF00FF00FF00FFull;
        v = (v | (v >> 8)) & 0x0000FFFF0000FFFFull;
        v = (v | (v >> 16)) & 0x00000000FFFFFFFFull;
        return static_cast<uint32_t>(v);
    };
    return {compact(m), compact(m >> 1)};
}

inline uint64_t mortonEncode(uint32_t tx, uint32_t ty) {
    auto spread = [](uint64_t v) {
        v = (v | (v << 16)) & 0x0000FFFF0000FFFFull;
        v = (v | (v << 8)) & 0x00FF00FF00FF00FFull;
        v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0Full;
        v = (v | (v << 2)) & 0x3333333333333333ull;
        v = (v | (v << 1)) & 0x5555555555555555ull;
        return v;
    };
    return spread(tx) | (spread(ty) << 1);
}

} // namespace pyramid
